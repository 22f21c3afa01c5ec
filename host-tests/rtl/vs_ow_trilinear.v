// vs_ow_trilinear: integer OpacityWeighted trilinear sample of one 2x2x2 tap
// set (volsample::fixed_point::opacity_weighted, Wittenbrink 1998 eqs. 9-12).
//
// Inputs
//   voxels : eight straight u8 voxels; voxel i (corner (i&1, (i>>1)&1, i>>2))
//            at voxels[32*i +: 32] = {a, b, g, r} (r in the low byte)
//   fx, fy, fz : fractions of the position, F fractional bits each (4 <= F <= 12)
// Outputs (U8.8; 65280 = opacity 1)
//   r, g, b : associated color C~, a : opacity alpha
//
// Arithmetic (all exact integers, one rounding per output, as in the Rust kernel):
//   per axis  p0 = 2^F - f, p1 = f
//   w_i       = px * py * pz                     (exact, sum of w_i = 2^S, S = 3F)
//   omega_i   = w_i * alpha_i                    (exact)
//   S_a       = sum omega_i,  S_c = sum omega_i * C_i (per channel, exact)
//   a         = floor(256*S_a / 2^S + 1/2)           round half up
//             = (256*S_a + 2^(S-1)) >> S
//   c         = floor(256*S_c / (255*2^S) + 1/2)     round half up
//             = floor((512*S_c + 255*2^S) / (510*2^S))
//             = floor(((512*S_c + 255*2^S) >> (S+1)) / 255)   (nested floors)
// Widths: w_i <= 2^S (S+1 bits); omega_i, S_a <= 255*2^S < 2^(S+8);
//   S_c <= 255^2 * 2^S < 2^(S+16); 512*S_c + 255*2^S < 2^(S+26);
//   the quotient by 2^(S+1) is <= 256*65025 + 127 < 2^24 (vs_div255's domain);
//   a <= 65280 and c <= a (S_c <= 255*S_a, monotone rounding), so 16 bits hold them.
//
// Synthesizable Verilog-2005, combinational (register the ports to pipeline).
module vs_ow_trilinear #(
    parameter F = 8
) (
    input  wire [255:0] voxels,
    input  wire [F-1:0] fx,
    input  wire [F-1:0] fy,
    input  wire [F-1:0] fz,
    output wire [15:0]  r,
    output wire [15:0]  g,
    output wire [15:0]  b,
    output wire [15:0]  a
);
    localparam S = 3 * F;

    // Per-axis factors: index 0 = low corner (2^F - f), 1 = high corner (f).
    wire [F:0] one_f = 1 << F;
    wire [F:0] px0 = one_f - fx, px1 = {1'b0, fx};
    wire [F:0] py0 = one_f - fy, py1 = {1'b0, fy};
    wire [F:0] pz0 = one_f - fz, pz1 = {1'b0, fz};

    // Exact sums.
    reg [S+7:0]  s_a;
    reg [S+15:0] s_r, s_g, s_b;
    reg [F:0]    px, py, pz;
    reg [S:0]    w;
    reg [S+7:0]  omega;
    integer i;
    always @* begin
        s_a = 0;
        s_r = 0;
        s_g = 0;
        s_b = 0;
        px = 0;
        py = 0;
        pz = 0;
        w = 0;
        omega = 0;
        for (i = 0; i < 8; i = i + 1) begin
            px = ((i & 1) != 0) ? px1 : px0;
            py = ((i & 2) != 0) ? py1 : py0;
            pz = ((i & 4) != 0) ? pz1 : pz0;
            w = px * py * pz;
            omega = w * voxels[32*i+24 +: 8];
            s_a = s_a + omega;
            s_r = s_r + omega * voxels[32*i    +: 8];
            s_g = s_g + omega * voxels[32*i+8  +: 8];
            s_b = s_b + omega * voxels[32*i+16 +: 8];
        end
    end

    // The high bits of a_q, q_* and c_* are zero by the width proof above; only the
    // proven-live bits are used.
    /* verilator lint_off UNUSEDSIGNAL */
    // alpha: round half up of 256*S_a / 2^S.
    wire [S+16:0] one_a = 1;
    wire [S+16:0] a_num = ({9'd0, s_a} << 8) + (one_a << (S - 1));
    wire [S+16:0] a_q = a_num >> S;
    assign a = a_q[15:0];

    // Colors: round half up of 256*S_c / (255*2^S), as floor(floor(n / 2^(S+1)) / 255).
    wire [S+25:0] half_c = 255;
    wire [S+25:0] n_r = ({10'd0, s_r} << 9) + (half_c << S);
    wire [S+25:0] n_g = ({10'd0, s_g} << 9) + (half_c << S);
    wire [S+25:0] n_b = ({10'd0, s_b} << 9) + (half_c << S);
    wire [S+25:0] q_r = n_r >> (S + 1);
    wire [S+25:0] q_g = n_g >> (S + 1);
    wire [S+25:0] q_b = n_b >> (S + 1);
    wire [16:0] c_r, c_g, c_b;
    /* verilator lint_on UNUSEDSIGNAL */
    vs_div255 div_r (.x(q_r[23:0]), .q(c_r));
    vs_div255 div_g (.x(q_g[23:0]), .q(c_g));
    vs_div255 div_b (.x(q_b[23:0]), .q(c_b));
    assign r = c_r[15:0];
    assign g = c_g[15:0];
    assign b = c_b[15:0];
endmodule
