// vs_div255: q = floor(x / 255) for x < 2^24, by the exact multiply-shift
// q = (x * 16843010) >> 32, where 16843010 = ceil(2^32 / 255).
//
// Proof of exactness: 255 * 16843010 = 2^32 + 254, so x * 16843010 / 2^32
// = x/255 + x*254/(255*2^32). The fractional part of x/255 is at most 254/255,
// and x*254/(255*2^32) < 1/255 for x < 2^32/254 (> 2^24), so the sum never
// reaches the next integer. (host-tests/tests/vectors.rs checks every x < 2^24.)
//
// Synthesizable Verilog-2005, combinational.
module vs_div255 (
    input  wire [23:0] x,
    output wire [16:0] q
);
    localparam [24:0] MAGIC = 25'd16843010;
    /* verilator lint_off UNUSEDSIGNAL */
    wire [48:0] prod = x * MAGIC; // prod[31:0] is the discarded fraction
    /* verilator lint_on UNUSEDSIGNAL */
    assign q = prod[48:32];
endmodule
