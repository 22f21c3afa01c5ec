// vs_downsample_ob: one coarse voxel of integer opacity-based downsampling of u8 associated
// voxels (volsample::downsample::integer::downsample_level_int with IntOpacityBased).
//
// Inputs
//   taps  : the 4x4x4 fine voxels, tap t = i + 4j + 16k (fine voxel (2X-1+i, 2Y-1+j,
//           2Z-1+k) of coarse voxel (X, Y, Z)) at taps[32*t +: 32] = {a, b~, g~, r~}
//   a_raw : outer filter tap a, Q0.16, at most 2^15; the taps are (a, b, b, a) with
//           b = 2^15 - a (exact), so the four sum to 2^16
// Output
//   v     : the coarse voxel {a', b~', g~', r~'}, u8 associated
//
// Arithmetic (every rounding named; as the Rust kernel):
//   x_t   = min(C~_t, alpha_t) per color, alpha_t for opacity (the min is a no-op for valid
//           voxels)
//   S_x   = sum over i, j, k of w_i*w_j*w_k*x_t (exact; evaluated separably along x, then y,
//           then z: P = a*(x_0 + x_3) + b*(x_1 + x_2) per pass), in units of 2^-48
//   g_x   = floor(S_x / 2^40 + 1/2) = (S_x + 2^39) >> 40            round half up
//           (8 guard bits: g = 256*level, at most 65280)
//   A     = g_alpha,  C_x = min(g_x, A) for each color
//   G     = 2*65280 - A                         (the doubled-distance gain 2 - alpha)
//   alpha'= floor(A*G / (2^16*255) + 1/2)                             round half up
//         = floor(((A*G + 255*2^15) >> 16) / 255)                     (nested floors)
//   c'    = floor(C_x*G / (2^16*255) + 1/2), likewise                 round half up
// Widths: x-pass sums < 2^24, y-pass < 2^40, S_x <= 255*2^48 < 2^56; g_x <= 65280
//   (16 bits); G <= 130560 (17 bits); A*G <= 65280^2, plus 255*2^15 < 2^32; shifted by 16 it
//   is < 2^17 (vs_div255's domain); alpha' <= 255 (alpha*(2 - alpha) <= 1), c' <= alpha'.
//
// Synthesizable Verilog-2005, combinational.
module vs_downsample_ob (
    input  wire [2047:0] taps,
    input  wire [15:0]   a_raw,
    output wire [31:0]   v
);
    wire [15:0] ta = a_raw;
    wire [15:0] tb = 16'd32768 - a_raw;

    // Exact sums S_x per channel k (0 = r, 1 = g, 2 = b, 3 = alpha).
    reg [4*56-1:0] s;
    reg [16*24-1:0] p1; // x passes, index j + 4k
    reg [4*40-1:0]  p2; // y passes, index k
    reg [7:0]       x0, x1, x2, x3, al;
    integer ch, j, k, t;
    always @* begin
        s = 0;
        p1 = 0;
        p2 = 0;
        x0 = 0;
        x1 = 0;
        x2 = 0;
        x3 = 0;
        al = 0;
        for (ch = 0; ch < 4; ch = ch + 1) begin
            for (k = 0; k < 4; k = k + 1) begin
                for (j = 0; j < 4; j = j + 1) begin
                    t = 4 * j + 16 * k;
                    x0 = taps[32*t + 8*ch +: 8];
                    x1 = taps[32*(t+1) + 8*ch +: 8];
                    x2 = taps[32*(t+2) + 8*ch +: 8];
                    x3 = taps[32*(t+3) + 8*ch +: 8];
                    if (ch != 3) begin
                        al = taps[32*t + 24 +: 8];
                        if (x0 > al) x0 = al;
                        al = taps[32*(t+1) + 24 +: 8];
                        if (x1 > al) x1 = al;
                        al = taps[32*(t+2) + 24 +: 8];
                        if (x2 > al) x2 = al;
                        al = taps[32*(t+3) + 24 +: 8];
                        if (x3 > al) x3 = al;
                    end
                    p1[24*(j + 4*k) +: 24] = ta * ({16'd0, x0} + {16'd0, x3})
                                           + tb * ({16'd0, x1} + {16'd0, x2});
                end
                p2[40*k +: 40] = ta * ({16'd0, p1[24*(4*k)   +: 24]} + {16'd0, p1[24*(4*k+3) +: 24]})
                               + tb * ({16'd0, p1[24*(4*k+1) +: 24]} + {16'd0, p1[24*(4*k+2) +: 24]});
            end
            s[56*ch +: 56] = ta * ({16'd0, p2[0 +: 40]} + {16'd0, p2[120 +: 40]})
                           + tb * ({16'd0, p2[40 +: 40]} + {16'd0, p2[80 +: 40]});
        end
    end

    // Guarded means (round half up): at most 65280, so 16 bits hold them.
    wire [56:0] half_g = 57'd1 << 39;
    /* verilator lint_off UNUSEDSIGNAL */
    wire [56:0] ga = ({1'b0, s[168 +: 56]} + half_g) >> 40;
    wire [56:0] gr = ({1'b0, s[0 +: 56]} + half_g) >> 40;
    wire [56:0] gg = ({1'b0, s[56 +: 56]} + half_g) >> 40;
    wire [56:0] gb = ({1'b0, s[112 +: 56]} + half_g) >> 40;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [15:0] a_g = ga[15:0];
    wire [15:0] c_r = (gr[15:0] > a_g) ? a_g : gr[15:0];
    wire [15:0] c_g = (gg[15:0] > a_g) ? a_g : gg[15:0];
    wire [15:0] c_b = (gb[15:0] > a_g) ? a_g : gb[15:0];
    wire [16:0] gain = 17'd130560 - a_g;

    // Doubled-distance correction, round half up: x' = floor(((x*G + 255*2^15) >> 16) / 255).
    wire [63:0] xs = {a_g, c_b, c_g, c_r};
    genvar q;
    generate
        for (q = 0; q < 4; q = q + 1) begin : finish
            // n[15:0] is divided away, d[16:8] is zero (d <= 255): unused by design.
            /* verilator lint_off UNUSEDSIGNAL */
            wire [32:0] n = xs[16*q +: 16] * gain + 33'd8355840;
            wire [16:0] d;
            /* verilator lint_on UNUSEDSIGNAL */
            vs_div255 div (.x({7'd0, n[32:16]}), .q(d));
            assign v[8*q +: 8] = d[7:0];
        end
    endgenerate
endmodule
