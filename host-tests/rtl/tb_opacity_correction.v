// Test bench: vs_opacity_correction against `volsample vectors --kernel opacity-correction`.
// Input word: s {a, b, g, r} at bits 63:0, ratio_raw at 127:64, ratio_f32 at 159:128 (not
// read: ratio_raw is the kernel's input); output word {a, b, g, r}, 16 bits each.
// The tables are read from the working directory (the vector directory) unless the DUT's
// *_HEX parameters say otherwise.
// Plusargs: +INPUTS=<inputs.hex> +EXPECTED=<expected.hex>; parameter N (-P).
// Prints every mismatch (the first 20 in full) and one final line starting with "PASS:" or
// "FAIL:" (run.sh greps it).
module tb_opacity_correction;
    parameter N = 10000;

    reg [159:0] in_mem  [0:N-1];
    reg [63:0]  exp_mem [0:N-1];
    reg [159:0] in_w;
    wire [63:0] got;

    vs_opacity_correction dut (.s(in_w[63:0]), .ratio_raw(in_w[127:64]), .out(got));

    reg [8*1024-1:0] in_file, exp_file;
    integer i, errors;
    initial begin
        if (!$value$plusargs("INPUTS=%s", in_file) || !$value$plusargs("EXPECTED=%s", exp_file)) begin
            $display("FAIL: tb_opacity_correction needs +INPUTS=<file> +EXPECTED=<file>");
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
                    $display("MISMATCH vector %0d: got %h expected %h input %h", i, got, exp_mem[i], in_mem[i]);
            end
        end
        if (errors == 0)
            $display("PASS: vs_opacity_correction: %0d vectors, 0 mismatches", N);
        else
            $display("FAIL: vs_opacity_correction: %0d vectors, %0d mismatches", N, errors);
        $finish;
    end
endmodule
