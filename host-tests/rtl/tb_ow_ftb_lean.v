// Test bench: vs_ow_ftb_lean (resource-lean OW trilinear sample + front-to-back step) against
// `volsample vectors`, with the inputs of the pipelined bench (tb_ow_ftb_pipe.cpp): the
// sample of vector i of `opacity-weighted-trilinear` (+INPUTS, +EXPECTED), composited behind
// the accumulator acc of vector i of `composite-front-to-back` (the low 64 bits of its
// inputs.hex, +ACC; default ../composite-front-to-back/inputs.hex, the sibling directory
// run.sh writes, relative to the working directory). The expected `out` is the manifest's
// step on the expected sample: out_x = acc_x + (T*s_x + 32640) div 65280, T = 65280 - acc_a.
// Both handshakes are exercised: the producer withholds in_valid on every seventh clock,
// the consumer drops out_ready on every fifth; the outputs must come back in order.
// Parameters F and N (-P). Prints every mismatch (the first 20 in full) and one final line
// starting with "PASS:" or "FAIL:" (run.sh greps it), with the measured latency (the fewest
// clocks from the edge that takes a sample to the edge that hands it over) and the clocks the
// run took.
module tb_ow_ftb_lean;
    parameter F = 8;
    parameter N = 10000;
    localparam IW = 256 + 3 * F;

    reg [IW-1:0] in_mem  [0:N-1];
    reg [63:0]   exp_mem [0:N-1];
    reg [127:0]  acc_mem [0:N-1];

    reg          clk, rst, in_valid, out_ready, pending;
    reg [IW-1:0] in_w;
    reg [63:0]   acc_w;
    wire         in_ready, out_valid;
    wire [63:0]  s, out;

    vs_ow_ftb_lean #(.F(F)) dut (
        .clk(clk), .rst(rst),
        .in_valid(in_valid), .in_ready(in_ready),
        .voxels(in_w[255:0]),
        .fx(in_w[256 +: F]),
        .fy(in_w[256 + F +: F]),
        .fz(in_w[256 + 2 * F +: F]),
        .acc(acc_w),
        .out_valid(out_valid), .out_ready(out_ready),
        .s(s), .out(out)
    );

    // The manifest's front-to-back step, with a plain division (not the datapath's ÷255).
    function [63:0] front_to_back;
        input [63:0] a, x;
        reg [63:0] t, r;
        integer k;
        begin
            t = 65280 - a[63:48];
            r = 0;
            for (k = 0; k < 4; k = k + 1)
                r[16*k +: 16] = a[16*k +: 16] + (t * x[16*k +: 16] + 32640) / 65280;
            front_to_back = r;
        end
    endfunction

    reg [8*1024-1:0] in_file, exp_file, acc_file;
    reg [63:0] want_out;
    integer sent, got, errors, cycle, latency, take_at [0:N-1];
    initial begin
        if (!$value$plusargs("INPUTS=%s", in_file) || !$value$plusargs("EXPECTED=%s", exp_file)) begin
            $display("FAIL: tb_ow_ftb_lean needs +INPUTS=<file> +EXPECTED=<file> [+ACC=<file>]");
            $finish;
        end
        if (!$value$plusargs("ACC=%s", acc_file))
            acc_file = "../composite-front-to-back/inputs.hex";
        $readmemh(in_file, in_mem);
        $readmemh(exp_file, exp_mem);
        $readmemh(acc_file, acc_mem);
        errors = 0;
        sent = 0;
        got = 0;
        latency = 0;
        clk = 0;
        rst = 1;
        in_valid = 0;
        pending = 0;
        out_ready = 0;
        in_w = 0;
        acc_w = 0;
        for (cycle = 0; cycle < 3; cycle = cycle + 1) begin
            #5 clk = 1;
            #5 clk = 0;
        end
        rst = 0;
        cycle = 0;
        while (got < N && cycle < 60 * N + 100) begin
            // Inputs change after the falling edge; the handshakes are sampled before the
            // rising edge, where the datapath sees them.
            // (once raised, in_valid stays up until the sample is taken)
            in_valid = (sent < N) && (pending || cycle % 7 != 6);
            if (sent < N) begin
                in_w = in_mem[sent];
                acc_w = acc_mem[sent][63:0];
            end
            out_ready = (cycle % 5 != 2);
            #4;
            if (out_valid && out_ready) begin
                // The shortest wait (no back-pressure) is the datapath's latency.
                if (latency == 0 || cycle - take_at[got] < latency)
                    latency = cycle - take_at[got];
                want_out = front_to_back(acc_mem[got][63:0], exp_mem[got]);
                // !== also flags X/Z, e.g. words missing from a short file.
                if (s !== exp_mem[got] || out !== want_out) begin
                    errors = errors + 1;
                    if (errors <= 20)
                        $display("MISMATCH vector %0d: got s %h out %h expected s %h out %h input %h acc %h",
                                 got, s, out, exp_mem[got], want_out, in_mem[got], acc_mem[got][63:0]);
                end
                got = got + 1;
            end
            pending = in_valid && !in_ready;
            if (in_valid && in_ready) begin
                take_at[sent] = cycle;
                sent = sent + 1;
            end
            #1 clk = 1;
            #5 clk = 0;
            cycle = cycle + 1;
        end
        if (got != N)
            $display("FAIL: vs_ow_ftb_lean F=%0d: %0d of %0d vectors came out", F, got, N);
        else if (errors == 0)
            $display("PASS: vs_ow_ftb_lean F=%0d: %0d vectors, 0 mismatches (latency %0d clocks, %0d clocks)",
                     F, N, latency, cycle);
        else
            $display("FAIL: vs_ow_ftb_lean F=%0d: %0d vectors, %0d mismatches", F, N, errors);
        $finish;
    end
endmodule
