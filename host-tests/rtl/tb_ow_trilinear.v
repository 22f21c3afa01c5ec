// Test bench: vs_ow_trilinear against `volsample vectors --kernel opacity-weighted-trilinear`.
// Plusargs: +INPUTS=<inputs.hex> +EXPECTED=<expected.hex>; parameters F and N (-P).
// Prints every mismatch (the first 20 in full) and one final line starting with
// "PASS:" or "FAIL:" (run.sh greps it; iverilog's $finish cannot set an exit code in
// Verilog-2005).
module tb_ow_trilinear;
    parameter F = 8;
    parameter N = 10000;
    localparam IW = 256 + 3 * F;

    reg [IW-1:0] in_mem  [0:N-1];
    reg [63:0]   exp_mem [0:N-1];
    reg [IW-1:0] in_w;
    wire [15:0]  r, g, b, a;
    wire [63:0]  got = {a, b, g, r};

    vs_ow_trilinear #(.F(F)) dut (
        .voxels(in_w[255:0]),
        .fx(in_w[256 +: F]),
        .fy(in_w[256 + F +: F]),
        .fz(in_w[256 + 2 * F +: F]),
        .r(r), .g(g), .b(b), .a(a)
    );

    reg [8*1024-1:0] in_file, exp_file;
    integer i, errors;
    initial begin
        if (!$value$plusargs("INPUTS=%s", in_file) || !$value$plusargs("EXPECTED=%s", exp_file)) begin
            $display("FAIL: tb_ow_trilinear needs +INPUTS=<file> +EXPECTED=<file>");
            $finish;
        end
        $readmemh(in_file, in_mem);
        $readmemh(exp_file, exp_mem);
        errors = 0;
        in_w = 0;
        for (i = 0; i < N; i = i + 1) begin
            in_w = in_mem[i];
            #1;
            // !== also flags X/Z, e.g. words missing from a short file.
            if (got !== exp_mem[i]) begin
                errors = errors + 1;
                if (errors <= 20)
                    $display("MISMATCH vector %0d: got %h expected %h input %h", i, got, exp_mem[i], in_mem[i]);
            end
        end
        if (errors == 0)
            $display("PASS: vs_ow_trilinear F=%0d: %0d vectors, 0 mismatches", F, N);
        else
            $display("FAIL: vs_ow_trilinear F=%0d: %0d vectors, %0d mismatches", F, N, errors);
        $finish;
    end
endmodule
