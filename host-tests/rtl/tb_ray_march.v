// Test bench: vs_ray_march against `volsample vectors --kernel
// ray-march-opacity-weighted-trilinear` (NEAREST = 0) or `...-nearest` (NEAREST = 1).
// Input word (the manifest's layout): voxel i at bits 32*i +: 32 ({a, b, g, r}), then px, py,
// pz (F+2 bits each), dx, dy, dz (F+3 bits each, two's complement), n (5), ratio_raw (64),
// ratio_f32 (32, not read), a_stop (16), bg_r, bg_g, bg_b, bg_a (16 each); output word
// {samples (5), a, b, g, r (16 each)}. The voxel memory model answers the eight read ports
// from the current word's voxels in the same cycle; the correction tables are read from the
// working directory (the vector directory).
// Plusargs: +INPUTS=<inputs.hex> +EXPECTED=<expected.hex>; parameters F, NEAREST, N (-P).
// Prints every mismatch (the first 20 in full), the clock cycles used, and one final line
// starting with "PASS:" or "FAIL:" (run.sh greps it).
module tb_ray_march;
    parameter F = 8;
    parameter NEAREST = 0;
    parameter N = 10000;
    localparam P0 = 2048;
    localparam D0 = P0 + 3 * (F + 2);
    localparam N0 = D0 + 3 * (F + 3);
    localparam R0 = N0 + 5;
    localparam AS0 = R0 + 64 + 32;
    localparam BG0 = AS0 + 16;
    localparam IW = BG0 + 64;

    reg [IW-1:0] in_mem  [0:N-1];
    reg [68:0]   exp_mem [0:N-1];
    reg [IW-1:0] in_w;
    reg          clk, rst, start;
    wire [47:0]  addr;
    wire [255:0] vox;
    wire         done;
    wire [63:0]  out;
    wire [4:0]   samples;
    wire [68:0]  got = {samples, out};

    genvar j;
    generate
        for (j = 0; j < 8; j = j + 1) begin : port
            assign vox[32*j +: 32] = in_w[32*addr[6*j +: 6] +: 32];
        end
    endgenerate

    vs_ray_march #(.F(F), .NEAREST(NEAREST)) dut (
        .clk(clk), .rst(rst), .start(start),
        .p(in_w[P0 +: 3*(F+2)]), .d(in_w[D0 +: 3*(F+3)]), .n(in_w[N0 +: 5]),
        .ratio_raw(in_w[R0 +: 64]), .a_stop(in_w[AS0 +: 16]), .bg(in_w[BG0 +: 64]),
        .addr(addr), .vox(vox), .done(done), .out(out), .samples(samples)
    );

    always #5 clk = ~clk;

    reg [8*1024-1:0] in_file, exp_file;
    reg [8*16-1:0]   filter;
    integer i, errors, cycles, timeout;
    initial begin
        filter = NEAREST ? "nearest" : "trilinear";
        if (!$value$plusargs("INPUTS=%s", in_file) || !$value$plusargs("EXPECTED=%s", exp_file)) begin
            $display("FAIL: tb_ray_march needs +INPUTS=<file> +EXPECTED=<file>");
            $finish;
        end
        $readmemh(in_file, in_mem);
        $readmemh(exp_file, exp_mem);
        errors = 0;
        cycles = 0;
        in_w = 0;
        clk = 0;
        rst = 1;
        start = 0;
        @(negedge clk);
        rst = 0;
        for (i = 0; i < N; i = i + 1) begin
            in_w = in_mem[i];
            start = 1;
            @(negedge clk);
            start = 0;
            timeout = 0;
            while (!done && timeout < 40) begin
                @(negedge clk);
                timeout = timeout + 1;
            end
            cycles = cycles + timeout + 1;
            if (!done || got !== exp_mem[i]) begin
                errors = errors + 1;
                if (errors <= 20)
                    $display("MISMATCH vector %0d: got %h expected %h (done %b)", i, got, exp_mem[i], done);
            end
        end
        if (errors == 0)
            $display("PASS: vs_ray_march %0s F=%0d: %0d vectors, 0 mismatches (%0d clock cycles)", filter, F, N, cycles);
        else
            $display("FAIL: vs_ray_march %0s F=%0d: %0d vectors, %0d mismatches", filter, F, N, errors);
        $finish;
    end
endmodule
