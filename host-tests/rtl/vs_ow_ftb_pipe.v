// vs_ow_ftb_pipe: pipelined OpacityWeighted trilinear sample + front-to-back step, one
// sample per clock, fixed latency (a valid pipe: no back-pressure, every stage advances on
// every clock), parameter F (4..12).
//
// Per clock with in_valid: voxels (eight straight u8 voxels, voxel i = corner (i&1, (i>>1)&1,
// i>>2) at voxels[32*i +: 32] = {a, b, g, r}), fx, fy, fz (F fractional bits) and acc (the
// U8.8 accumulator {a, b, g, r} in front of the sample). LATENCY = 6 clocks later, with
// out_valid: s = the sample (bit-identical to vs_ow_trilinear) and out =
// front_to_back(acc, s) (bit-identical to vs_composite_ftb).
//
// Stages (each ends in a register; the arithmetic is vs_ow_trilinear's and
// vs_composite_ftb's, split):
//   1. w_i = px*py*pz                        (exact, S+1 bits, S = 3F)
//   2. omega_i = w_i*alpha_i                 (exact, S+8 bits)
//   3. S_a = sum omega_i, S_c = sum omega_i*C_i (exact)
//   4. a = (256*S_a + 2^(S-1)) >> S; c = floor(((512*S_c + 255*2^S) >> (S+1)) / 255)
//                                            (round half up; the sample s)
//   5. n_x = (65280 - acc_a)*s_x + 32640     (exact, 32 bits)
//   6. out_x = acc_x + floor((n_x >> 8) / 255)   (round half up); s delayed to match
// rst (synchronous, active high) clears the valid bits only.
//
// Synthesizable Verilog-2005.
module vs_ow_ftb_pipe #(
    parameter F = 8
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         in_valid,
    input  wire [255:0] voxels,
    input  wire [F-1:0] fx,
    input  wire [F-1:0] fy,
    input  wire [F-1:0] fz,
    input  wire [63:0]  acc,
    output wire         out_valid,
    output wire [63:0]  s,
    output wire [63:0]  out
);
    localparam S = 3 * F;
    localparam LATENCY = 6;
    localparam [15:0] ONE = 16'd65280;

    reg [LATENCY-1:0] v;
    always @(posedge clk) begin
        if (rst)
            v <= 0;
        else
            v <= {v[LATENCY-2:0], in_valid};
    end
    assign out_valid = v[LATENCY-1];

    // The voxels travel to stage 3, the accumulator to stage 6, the sample from 4 to 6.
    reg [255:0] vox1, vox2;
    reg [63:0]  acc1, acc2, acc3, acc4, acc5;
    reg [63:0]  s5, s6, s7;
    always @(posedge clk) begin
        vox1 <= voxels;
        vox2 <= vox1;
        acc1 <= acc;
        acc2 <= acc1;
        acc3 <= acc2;
        acc4 <= acc3;
        acc5 <= acc4;
        s6 <= s5;
        s7 <= s6;
    end

    // Stage 1: weights.
    wire [F:0] one_f = 1 << F;
    wire [F:0] px0 = one_f - fx, px1 = {1'b0, fx};
    wire [F:0] py0 = one_f - fy, py1 = {1'b0, fy};
    wire [F:0] pz0 = one_f - fz, pz1 = {1'b0, fz};
    reg [8*(S+1)-1:0] w1;
    reg [8*(S+8)-1:0] om2;
    genvar i;
    generate
        for (i = 0; i < 8; i = i + 1) begin : corner
            wire [F:0] px = ((i & 1) != 0) ? px1 : px0;
            wire [F:0] py = ((i & 2) != 0) ? py1 : py0;
            wire [F:0] pz = ((i & 4) != 0) ? pz1 : pz0;
            wire [S:0] wi = px * py * pz;
            // Stage 2: omega_i = w_i * alpha_i.
            wire [S+7:0] om = w1[(S+1)*i +: S+1] * vox1[32*i+24 +: 8];
            always @(posedge clk) begin
                w1[(S+1)*i +: S+1] <= wi;
                om2[(S+8)*i +: S+8] <= om;
            end
        end
    endgenerate

    // Stage 3: exact sums.
    reg [S+7:0]  sa, s_a3;
    reg [S+15:0] sr, sg, sb, s_r3, s_g3, s_b3;
    reg [S+7:0]  o;
    integer k;
    always @* begin
        sa = 0;
        sr = 0;
        sg = 0;
        sb = 0;
        o = 0;
        for (k = 0; k < 8; k = k + 1) begin
            o = om2[(S+8)*k +: S+8];
            sa = sa + o;
            sr = sr + o * vox2[32*k    +: 8];
            sg = sg + o * vox2[32*k+8  +: 8];
            sb = sb + o * vox2[32*k+16 +: 8];
        end
    end
    always @(posedge clk) begin
        s_a3 <= sa;
        s_r3 <= sr;
        s_g3 <= sg;
        s_b3 <= sb;
    end

    // Stage 4: one rounding per output (vs_ow_trilinear's).
    /* verilator lint_off UNUSEDSIGNAL */
    wire [S+16:0] one_a = 1;
    wire [S+16:0] a_num = ({9'd0, s_a3} << 8) + (one_a << (S - 1));
    wire [S+16:0] a_q = a_num >> S;
    wire [S+25:0] half_c = 255;
    wire [S+25:0] n_r = ({10'd0, s_r3} << 9) + (half_c << S);
    wire [S+25:0] n_g = ({10'd0, s_g3} << 9) + (half_c << S);
    wire [S+25:0] n_b = ({10'd0, s_b3} << 9) + (half_c << S);
    wire [S+25:0] q_r = n_r >> (S + 1);
    wire [S+25:0] q_g = n_g >> (S + 1);
    wire [S+25:0] q_b = n_b >> (S + 1);
    wire [16:0] c_r, c_g, c_b;
    /* verilator lint_on UNUSEDSIGNAL */
    vs_div255 div_r (.x(q_r[23:0]), .q(c_r));
    vs_div255 div_g (.x(q_g[23:0]), .q(c_g));
    vs_div255 div_b (.x(q_b[23:0]), .q(c_b));
    always @(posedge clk)
        s5 <= {a_q[15:0], c_b[15:0], c_g[15:0], c_r[15:0]};

    // Stages 5 and 6: the compositing step (vs_composite_ftb's, split after the products).
    wire [15:0] t = ONE - acc4[63:48];
    reg [95:0] n6; // (n >> 8) per channel, 24 bits
    generate
        for (i = 0; i < 4; i = i + 1) begin : channel
            // n[7:0] is divided away and inc[16] is zero (inc <= T): unused by design.
            /* verilator lint_off UNUSEDSIGNAL */
            wire [31:0] n = t * s5[16*i +: 16] + 32'd32640;
            wire [16:0] inc;
            /* verilator lint_on UNUSEDSIGNAL */
            always @(posedge clk)
                n6[24*i +: 24] <= n[31:8];
            vs_div255 div (.x(n6[24*i +: 24]), .q(inc));
            reg [15:0] o6;
            always @(posedge clk)
                o6 <= acc5[16*i +: 16] + inc[15:0];
            assign out[16*i +: 16] = o6;
        end
    endgenerate
    assign s = s7;
endmodule
