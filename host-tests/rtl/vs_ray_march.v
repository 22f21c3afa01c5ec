// vs_ray_march: the integer ray marcher of one ray at integer sample positions
// (volsample::render::IntRayMarcher::march_positions, OpacityWeighted over a 4x4x4 volume of
// straight u8 voxels, trilinear (NEAREST = 0) or nearest neighbour (NEAREST = 1)), one sample
// per clock: address generation with edge clamping, voxel fetch from an external memory,
// sampling, opacity correction, front-to-back compositing, early termination, background.
//
// Interface (all registers on the rising edge of clk; rst is synchronous, active high)
//   start      : one-cycle pulse in IDLE: latches p, d, n, ratio_raw, a_stop, bg and begins
//   p          : first position, per axis F+2 bits unsigned, raw/2^F voxel, {pz, py, px}
//   d          : step between positions, per axis F+3 bits two's complement, {dz, dy, dx}
//   n          : number of positions p_k = p + k*d, k = 0..n-1 (0..31)
//   ratio_raw  : r = d/d' as U32.32; the opacity of every sample is corrected
//                (vs_opacity_correction) unless ratio_raw = 2^32 (r = 1)
//   a_stop     : U8.8 threshold, 1..65280: stop before a sample once acc_a >= a_stop
//   bg         : U8.8 background {a, b, g, r}
//   addr, vox  : voxel memory, 8 asynchronous read ports: vox[32*i +: 32] must be the voxel
//                ({a, b, g, r}, straight u8) at address addr[6*i +: 6] = x + 4y + 16z in the
//                same cycle
//   done       : one-cycle pulse with out = {a, b, g, r} (U8.8) and samples (the number
//                composited; the background is not counted)
//
// Per sample k (state RUN), all exact integer steps of the Rust code:
//   stop if acc_a >= a_stop or k = n (checked before the sample is read)
//   trilinear: index q = p_k >> F per axis (truncate), fraction p_k mod 2^F; tap i (corner
//              (i&1, (i>>1)&1, i>>2)) at (q + corner) clamped to 3 per axis (edge clamp);
//              sample = vs_ow_trilinear of the eight taps
//   nearest:   index q = min((p_k + 2^(F-1)) >> F, 3) per axis (round half up, clamp);
//              sample = vs_ow_nearest of that voxel (tap 0, fractions 0)
//   corrected: s = vs_opacity_correction(s, ratio_raw) when ratio_raw != 2^32
//   acc = vs_composite_ftb(acc, s); k = k + 1; p = p + d (two's complement, exact)
// then (state FINISH) out = vs_composite_ftb(acc, bg), the same step with the background.
// Latency: n + 2 cycles from start (fewer when the stop is reached) to done.
//
// Synthesizable Verilog-2005 (the correction tables are ROMs, see vs_opacity_correction).
module vs_ray_march #(
    parameter F = 8,
    parameter NEAREST = 0
) (
    input  wire           clk,
    input  wire           rst,
    input  wire           start,
    input  wire [3*F+5:0] p,
    input  wire [3*F+8:0] d,
    input  wire [4:0]     n,
    input  wire [63:0]    ratio_raw,
    input  wire [15:0]    a_stop,
    input  wire [63:0]    bg,
    output wire [47:0]    addr,
    input  wire [255:0]   vox,
    output reg            done,
    output reg  [63:0]    out,
    output reg  [4:0]     samples
);
    localparam [1:0] IDLE = 2'd0, RUN = 2'd1, FINISH = 2'd2;
    localparam PW = F + 4; // position register: F + 4 bits two's complement
    reg [1:0]    state;
    reg [3*PW-1:0] pos;      // {z, y, x}
    reg [3*PW-1:0] step;
    reg [4:0]    k, n_r;
    reg [63:0]   r_r, bg_r, acc;
    reg [15:0]   stop_r;

    // Address generation with edge clamping.
    wire [2*3-1:0] q;  // per axis 2-bit index
    wire [2*3-1:0] q1; // per axis the index + 1 clamped to 3
    wire [3*F-1:0] fr; // per axis fraction
    genvar ax, i;
    generate
        for (ax = 0; ax < 3; ax = ax + 1) begin : axis
            // Valid positions are in [0, 3*2^F]: the high bits are zero by the contract.
            /* verilator lint_off UNUSEDSIGNAL */
            wire [PW-1:0] pa = pos[PW*ax +: PW];
            wire [PW-1:0] pn = pa + {{(PW-F){1'b0}}, 1'b1, {(F-1){1'b0}}};
            /* verilator lint_on UNUSEDSIGNAL */
            wire [3:0]    it = (NEAREST != 0) ? pn[F +: 4] : pa[F +: 4];
            assign q[2*ax +: 2] = (it > 4'd3) ? 2'd3 : it[1:0];
            assign q1[2*ax +: 2] = (q[2*ax +: 2] == 2'd3) ? 2'd3 : q[2*ax +: 2] + 2'd1;
            assign fr[F*ax +: F] = (NEAREST != 0) ? {F{1'b0}} : pa[F-1:0];
        end
        for (i = 0; i < 8; i = i + 1) begin : tap
            wire [1:0] tx = ((i & 1) != 0 && NEAREST == 0) ? q1[1:0] : q[1:0];
            wire [1:0] ty = ((i & 2) != 0 && NEAREST == 0) ? q1[3:2] : q[3:2];
            wire [1:0] tz = ((i & 4) != 0 && NEAREST == 0) ? q1[5:4] : q[5:4];
            assign addr[6*i +: 6] = {tz, ty, tx};
        end
    endgenerate

    // Sample, correction, compositing.
    wire [15:0] sr, sg, sb, sa;
    generate
        if (NEAREST != 0) begin : nearest
            vs_ow_nearest #(.F(F)) smp (.voxels(vox), .fx(fr[F-1:0]), .fy(fr[2*F-1:F]),
                .fz(fr[3*F-1:2*F]), .r(sr), .g(sg), .b(sb), .a(sa));
        end else begin : trilinear
            vs_ow_trilinear #(.F(F)) smp (.voxels(vox), .fx(fr[F-1:0]), .fy(fr[2*F-1:F]),
                .fz(fr[3*F-1:2*F]), .r(sr), .g(sg), .b(sb), .a(sa));
        end
    endgenerate
    wire [63:0] s_raw = {sa, sb, sg, sr};
    wire [63:0] s_cor;
    vs_opacity_correction corr (.s(s_raw), .ratio_raw(r_r), .out(s_cor));
    wire        corr_on = (r_r != 64'h1_0000_0000);
    wire [63:0] s_in = (state == FINISH) ? bg_r : (corr_on ? s_cor : s_raw);
    wire [63:0] acc_next;
    vs_composite_ftb comp (.acc(acc), .s(s_in), .out(acc_next));
    wire        stop = (acc[63:48] >= stop_r) || (k == n_r);

    // Sign-extends a step component to the position width.
    function [PW-1:0] sext;
        input [F+2:0] v;
        sext = {v[F+2], v};
    endfunction

    always @(posedge clk) begin
        done <= 1'b0;
        if (rst) begin
            state <= IDLE;
            pos <= 0;
            step <= 0;
            k <= 0;
            n_r <= 0;
            r_r <= 0;
            bg_r <= 0;
            acc <= 0;
            stop_r <= 0;
            out <= 0;
            samples <= 0;
        end else begin
            case (state)
                IDLE: if (start) begin
                    pos <= {2'b00, p[2*(F+2) +: F+2], 2'b00, p[F+2 +: F+2], 2'b00, p[0 +: F+2]};
                    step <= {sext(d[2*(F+3) +: F+3]), sext(d[F+3 +: F+3]), sext(d[0 +: F+3])};
                    n_r <= n;
                    r_r <= ratio_raw;
                    stop_r <= a_stop;
                    bg_r <= bg;
                    acc <= 0;
                    k <= 0;
                    state <= RUN;
                end
                RUN: if (stop) begin
                    state <= FINISH;
                end else begin
                    acc <= acc_next;
                    k <= k + 5'd1;
                    pos <= {pos[2*PW +: PW] + step[2*PW +: PW], pos[PW +: PW] + step[PW +: PW],
                            pos[0 +: PW] + step[0 +: PW]};
                end
                FINISH: begin
                    out <= acc_next;
                    samples <= k;
                    done <= 1'b1;
                    state <= IDLE;
                end
                default: state <= IDLE;
            endcase
        end
    end
endmodule
