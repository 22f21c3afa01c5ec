// vs_composite_ftb: one integer front-to-back compositing step
// (volsample::fixed_point::composite::front_to_back): acc is in front of s.
//
// Ports are U8.8 samples packed {a, b, g, r} (r in bits 15:0, a in bits 63:48),
// opacity 1 = ONE = 65280, and c <= a <= ONE on input (the invariant of IntSample).
//
// Arithmetic (round half up, as in the Rust kernel):
//   T     = ONE - acc_a
//   out_x = acc_x + floor(T * s_x / ONE + 1/2)    for x in r, g, b, a
//         = acc_x + floor((T * s_x + ONE/2) / ONE)
//         = acc_x + floor(((T * s_x + 32640) >> 8) / 255)   (ONE = 255*256; nested floors)
// Widths: T * s_x + 32640 <= 65280^2 + 32640 < 2^32; shifted by 8 it is < 2^24
//   (vs_div255's domain); each increment is <= T, so out_a <= ONE and out_c <= out_a
//   (s_c <= s_a, monotone rounding): 16 bits hold every output.
//
// Synthesizable Verilog-2005, combinational.
module vs_composite_ftb (
    input  wire [63:0] acc,
    input  wire [63:0] s,
    output wire [63:0] out
);
    localparam [15:0] ONE = 16'd65280;
    wire [15:0] t = ONE - acc[63:48];

    genvar k;
    generate
        for (k = 0; k < 4; k = k + 1) begin : channel
            // n[7:0] is divided away and inc[16] is zero (inc <= T): unused by design.
            /* verilator lint_off UNUSEDSIGNAL */
            wire [31:0] n = t * s[16*k +: 16] + 32'd32640;
            wire [16:0] inc;
            /* verilator lint_on UNUSEDSIGNAL */
            vs_div255 div (.x(n[31:8]), .q(inc));
            assign out[16*k +: 16] = acc[16*k +: 16] + inc[15:0];
        end
    endgenerate
endmodule
