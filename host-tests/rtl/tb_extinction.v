// Test bench: vs_extinction against `volsample vectors --kernel extinction-weighted-trilinear`
// (NEAREST = 0) or `extinction-weighted-nearest` (NEAREST = 1), table size 2^B + 1.
// Input word: voxel i at bits 108*i +: 108 ({tau, ctau_b, ctau_g, ctau_r}, 27 bits each),
// fx, fy, fz (F bits each) from bit 864, ratio_raw (64 bits) above them, ratio_f32 (not
// read) on top; output word {a, b, g, r}, 16 bits each. The tables are read from the working
// directory (the vector directory).
// Plusargs: +INPUTS=<inputs.hex> +EXPECTED=<expected.hex>; parameters F, NEAREST, B, N (-P).
// Prints every mismatch (the first 20 in full) and one final line starting with "PASS:" or
// "FAIL:" (run.sh greps it).
module tb_extinction;
    parameter F = 8;
    parameter NEAREST = 0;
    parameter B = 8;
    parameter N = 10000;
    localparam IW = 864 + 3 * F + 96;

    reg [IW-1:0] in_mem  [0:N-1];
    reg [63:0]   exp_mem [0:N-1];
    reg [IW-1:0] in_w;
    wire [63:0]  got;

    vs_extinction #(.F(F), .NEAREST(NEAREST), .B(B)) dut (
        .voxels(in_w[863:0]),
        .fx(in_w[864 +: F]),
        .fy(in_w[864 + F +: F]),
        .fz(in_w[864 + 2 * F +: F]),
        .ratio_raw(in_w[864 + 3 * F +: 64]),
        .out(got)
    );

    reg [8*1024-1:0] in_file, exp_file;
    reg [8*16-1:0]   filter;
    integer i, errors;
    initial begin
        filter = NEAREST ? "nearest" : "trilinear";
        if (!$value$plusargs("INPUTS=%s", in_file) || !$value$plusargs("EXPECTED=%s", exp_file)) begin
            $display("FAIL: tb_extinction needs +INPUTS=<file> +EXPECTED=<file>");
            $finish;
        end
        $readmemh(in_file, in_mem);
        $readmemh(exp_file, exp_mem);
        errors = 0;
        in_w = 0;
        for (i = 0; i < N; i = i + 1) begin
            in_w = in_mem[i];
            #1;
            if (got !== exp_mem[i]) begin
                errors = errors + 1;
                if (errors <= 20)
                    $display("MISMATCH vector %0d: got %h expected %h", i, got, exp_mem[i]);
            end
        end
        if (errors == 0)
            $display("PASS: vs_extinction %0s F=%0d N=%0d: %0d vectors, 0 mismatches",
                     filter, F, (1 << B) + 1, N);
        else
            $display("FAIL: vs_extinction %0s F=%0d N=%0d: %0d vectors, %0d mismatches",
                     filter, F, (1 << B) + 1, N, errors);
        $finish;
    end
endmodule
