// vs_extinction: integer ExtinctionWeighted sample of one 2x2x2 tap set of fixed-point
// extinction voxels (volsample::fixed_point::extinction::IntExtinction, Kraus & Buerger
// 2008), trilinear (NEAREST = 0) or nearest neighbour (NEAREST = 1).
//
// Inputs
//   voxels    : eight voxels; voxel i (corner (i&1, (i>>1)&1, i>>2)) at voxels[108*i +: 108]
//               = {tau, ctau_b, ctau_g, ctau_r}, 27 bits each (ctau_r lowest), U7.20:
//               tau = D = optical depth per reference distance (<= 2^26), ctau = D*C (<= tau)
//   fx, fy, fz: fractions of the position, F fractional bits each (4 <= F <= 12)
//   ratio_raw : the step ratio r = d/d' as U32.32, floor(r*2^32 + 1/2)
// Output
//   out       : U8.8 sample {a, b, g, r} (65280 = opacity 1)
// Tables (ROMs loaded with $readmemh; the files `volsample vectors --kernel
// extinction-weighted-*` writes, entry j on line j), N = 2^B + 1 entries (--table-size):
//   PHI_HEX     Phi[j]  = floor(2^31*phi(j/2^B) + 1/2), phi(x) = (1 - e^-x)/x, 32 bits
//   EXP_HEX     E[j]    = floor(2^31*e^(-j/2^B) + 1/2), 32 bits
//   EXP_INT_HEX X[n-1]  = floor(2^32*e^(-n) + 1/2), n = 1..15, 32 bits
//
// Arithmetic (every rounding named; as the Rust kernel), k = 28 - B:
//   weights   trilinear: w_i of vs_trilinear_weights, s = 3F; nearest: weight 1 on
//             vs_nearest_tap's voxel, s = 0
//   t_i = min(tau_i, 2^26), c_i = min(ctau_i, t_i)                       (no-ops if valid)
//   S_t = sum w_i*t_i, S_c = sum w_i*c_i per channel                     exact, <= 2^(s+26)
//   x   = min((S_t*r + 2^(s+23)) >> (s+24), 16*2^28)          round half up, then saturate
//   x_c = min((S_c*r + 2^(s+23)) >> (s+24), 16*2^28)          likewise, per channel
//   interp(T, t) = T[t >> k]*(2^k - (t mod 2^k)) + T[(t >> k) + 1]*(t mod 2^k), t < 2^28
//                                                                        exact, <= 2^(31+k)
//   x < 2^28:       P = interp(Phi, x)
//                   a = (65280*x*P + 2^(58+k)) >> (59+k)                 round half up
//                   c = (65280*x_c*P + 2^(58+k)) >> (59+k)               round half up
//   x >= 2^28:      n = x >> 28; Q = 0 if n = 16, else X[n-1]*interp(E, x mod 2^28) (exact)
//                   a = (65280*(2^(63+k) - Q) + 2^(62+k)) >> (63+k)      round half up
//                   c = floor(a*S_c/S_t + 1/2) = floor((2*a*S_c + S_t) / (2*S_t))
//                                                                        round half up
// Widths: S_* < 2^(s+27); S*r < 2^(s+91); x < 2^33 after saturation; P <= 2^(31+k);
//   65280*x*P < 2^(75+k); Q < 2^(62+k); 65280*2^(63+k) < 2^(79+k); a <= 65280;
//   2*a*S_c + S_t < 2^(s+44); c <= a (S_c <= S_t).
//
// Synthesizable Verilog-2005, combinational (asynchronous ROM reads; the three dividers
// by S_t are the expensive part).
module vs_extinction #(
    parameter F = 8,
    parameter NEAREST = 0,
    parameter B = 8,
    parameter PHI_HEX = "table_phi.hex",
    parameter EXP_HEX = "table_exp.hex",
    parameter EXP_INT_HEX = "table_exp_int.hex"
) (
    input  wire [863:0] voxels,
    input  wire [F-1:0] fx,
    input  wire [F-1:0] fy,
    input  wire [F-1:0] fz,
    input  wire [63:0]  ratio_raw,
    output wire [63:0]  out
);
    localparam [15:0] ONE = 16'd65280;
    localparam S  = (NEAREST != 0) ? 0 : 3 * F;  // log2 of the weights' sum
    localparam SW = S + 27;                // width of a sum
    localparam K  = 28 - B;                // argument bits below a table index
    localparam NT = (1 << B) + 1;          // table entries

    reg [31:0] phi     [0:NT-1];
    reg [31:0] exp_t   [0:NT-1];
    reg [31:0] exp_int [0:14];
    initial begin
        $readmemh(PHI_HEX, phi);
        $readmemh(EXP_HEX, exp_t);
        $readmemh(EXP_INT_HEX, exp_int);
    end

    // Clamped channels of voxel i: cl[108*i + 27*ch +: 27], ch 0..2 colors, 3 tau.
    reg [863:0] cl;
    reg [26:0]  tv, cv;
    integer i, ch;
    always @* begin
        cl = 0;
        tv = 0;
        cv = 0;
        for (i = 0; i < 8; i = i + 1) begin
            tv = voxels[108*i + 81 +: 27];
            if (tv > 27'h4000000)
                tv = 27'h4000000;
            cl[108*i + 81 +: 27] = tv;
            for (ch = 0; ch < 3; ch = ch + 1) begin
                cv = voxels[108*i + 27*ch +: 27];
                if (cv > tv)
                    cv = tv;
                cl[108*i + 27*ch +: 27] = cv;
            end
        end
    end

    // Exact sums per channel (0..2 colors, 3 tau) at sums[SW*ch +: SW].
    wire [4*SW-1:0] sums;
    genvar g;
    generate
        if (NEAREST != 0) begin : nearest
            wire [107:0] v;
            vs_nearest_tap #(.F(F), .VW(108)) tap (.voxels(cl), .fx(fx), .fy(fy), .fz(fz), .v(v));
            assign sums = v;
        end else begin : trilinear
            wire [8*(S+1)-1:0] w;
            vs_trilinear_weights #(.F(F)) weights (.fx(fx), .fy(fy), .fz(fz), .w(w));
            reg [4*SW-1:0] acc;
            reg [SW-1:0]   a1;
            integer j, c;
            always @* begin
                acc = 0;
                a1 = 0;
                for (c = 0; c < 4; c = c + 1) begin
                    a1 = 0;
                    for (j = 0; j < 8; j = j + 1)
                        a1 = a1 + w[(S+1)*j +: S+1] * cl[108*j + 27*c +: 27];
                    acc[SW*c +: SW] = a1;
                end
            end
            assign sums = acc;
        end
    endgenerate
    wire [SW-1:0] s_t = sums[3*SW +: SW];

    // Step depths x (tau) and x_c (colors): xs[33*ch +: 33], round half up then saturate.
    // The colors' x_c are read only where x < 2^28, so x_c <= x < 2^28: their top bits are
    // unused by design.
    /* verilator lint_off UNUSEDSIGNAL */
    wire [4*33-1:0] xs;
    /* verilator lint_on UNUSEDSIGNAL */
    generate
        for (g = 0; g < 4; g = g + 1) begin : depth
            wire [SW+63:0] half = 1;
            wire [SW+63:0] num = sums[SW*g +: SW] * ratio_raw + (half << (S + 23));
            /* verilator lint_off UNUSEDSIGNAL */
            wire [SW+63:0] q = num >> (S + 24);
            /* verilator lint_on UNUSEDSIGNAL */
            wire [SW+63:0] lim = half << 32;
            assign xs[33*g +: 33] = (q >= lim) ? 33'h100000000 : q[32:0];
        end
    endgenerate
    wire [32:0] x = xs[99 +: 33];

    // Table reads at t = x mod 2^28.
    wire [B:0]   ti0 = {1'b0, x[27:K]};
    wire [B:0]   ti1 = ti0 + {{B{1'b0}}, 1'b1};
    wire [K:0]   tf = {1'b0, x[K-1:0]};
    wire [K:0]   tf_c = {1'b1, {K{1'b0}}} - tf;
    wire [31+K:0] p_phi = phi[ti0] * tf_c + phi[ti1] * tf;
    wire [31+K:0] p_exp = exp_t[ti0] * tf_c + exp_t[ti1] * tf;
    wire [4:0]   n = x[32:28];
    wire [3:0]   n1 = n[3:0] - 4'd1;
    wire [62+K:0] q_e = (n == 5'd0 || n == 5'd16) ? 0 : exp_int[n1] * p_exp;

    // alpha (and the colors for x < 1).
    wire [79+K:0] one = 1;
    /* verilator lint_off UNUSEDSIGNAL */
    wire [79+K:0] a_exp_n = ONE * ((one << (63 + K)) - {17'd0, q_e}) + (one << (62 + K));
    wire [79+K:0] a_exp = a_exp_n >> (63 + K);
    /* verilator lint_on UNUSEDSIGNAL */
    wire [15:0] a_big = a_exp[15:0];
    wire lt1 = (n == 5'd0); // x < 1
    generate
        for (g = 0; g < 4; g = g + 1) begin : sample
            wire [75+K:0] one_s = 1;
            wire [75+K:0] num = ONE * xs[33*g +: 28] * p_phi + (one_s << (58 + K));
            /* verilator lint_off UNUSEDSIGNAL */
            wire [75+K:0] q = num >> (59 + K);
            /* verilator lint_on UNUSEDSIGNAL */
            wire [15:0] v_small = q[15:0];
            if (g == 3) begin : alpha
                assign out[63:48] = lt1 ? v_small : a_big;
            end else begin : color
                // x >= 1: c = floor((2*a*S_c + S_t) / (2*S_t)), S_t > 0 there.
                wire [SW+15:0] prod = a_big * sums[SW*g +: SW];
                wire [S+44:0] num_c = {prod, 1'b0} + {18'd0, s_t};
                wire [S+44:0] den = {17'd0, s_t, 1'b0};
                /* verilator lint_off UNUSEDSIGNAL */
                wire [S+44:0] quo = num_c / den; // <= a: 16 bits
                /* verilator lint_on UNUSEDSIGNAL */
                assign out[16*g +: 16] = lt1 ? v_small : quo[15:0];
            end
        end
    endgenerate
endmodule
