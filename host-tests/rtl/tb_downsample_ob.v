// Test bench: vs_downsample_ob against `volsample vectors --kernel downsample-opacity-based`.
// Input word: tap t at bits 32*t +: 32 ({a, b~, g~, r~}), a_raw at bits 2063:2048; output
// word {a, b~, g~, r~}, 8 bits each (the manifest's layouts).
// Plusargs: +INPUTS=<inputs.hex> +EXPECTED=<expected.hex>; parameter N (-P).
// Prints every mismatch (the first 20 in full) and one final line starting with "PASS:" or
// "FAIL:" (run.sh greps it).
module tb_downsample_ob;
    parameter N = 10000;

    reg [2063:0] in_mem  [0:N-1];
    reg [31:0]   exp_mem [0:N-1];
    reg [2063:0] in_w;
    wire [31:0]  got;

    vs_downsample_ob dut (.taps(in_w[2047:0]), .a_raw(in_w[2063:2048]), .v(got));

    reg [8*1024-1:0] in_file, exp_file;
    integer i, errors;
    initial begin
        if (!$value$plusargs("INPUTS=%s", in_file) || !$value$plusargs("EXPECTED=%s", exp_file)) begin
            $display("FAIL: tb_downsample_ob needs +INPUTS=<file> +EXPECTED=<file>");
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
                    $display("MISMATCH vector %0d: got %h expected %h a_raw %h", i, got, exp_mem[i], in_mem[i][2063:2048]);
            end
        end
        if (errors == 0)
            $display("PASS: vs_downsample_ob: %0d vectors, 0 mismatches", N);
        else
            $display("FAIL: vs_downsample_ob: %0d vectors, %0d mismatches", N, errors);
        $finish;
    end
endmodule
