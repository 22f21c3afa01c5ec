// vs_separate_trilinear: integer Separate trilinear sample of one 2x2x2 tap set
// (volsample::fixed_point::separate, Levoy's interpolate-then-multiply baseline).
//
// Inputs
//   voxels : eight straight u8 voxels; voxel i (corner (i&1, (i>>1)&1, i>>2))
//            at voxels[32*i +: 32] = {a, b, g, r} (r in the low byte)
//   fx, fy, fz : fractions of the position, F fractional bits each (4 <= F <= 12)
// Outputs (U8.8; 65280 = opacity 1)
//   r, g, b : associated color C~, a : opacity alpha
//
// Arithmetic (exact sums, then three roundings, all round half up, as in the Rust kernel):
//   w_i  = trilinear weights (vs_trilinear_weights), sum 2^S, S = 3F
//   S_a  = sum w_i * alpha_i,  S_C = sum w_i * C_i (per channel, exact)
//   a    = floor(256*S_a / 2^S + 1/2) = (256*S_a + 2^(S-1)) >> S        round half up
//   C    = floor(256*S_C / 2^S + 1/2) = (256*S_C + 2^(S-1)) >> S        round half up
//          (straight color, U8.8, internal)
//   c    = floor(a*C / 65280 + 1/2) = floor((a*C + 32640) / 65280)     round half up
//        = floor(((a*C + 32640) >> 8) / 255)                           (nested floors)
// Widths: S_a, S_C <= 255*2^S < 2^(S+8); 256*S + 2^(S-1) < 2^(S+16); a, C <= 65280;
//   a*C + 32640 < 2^32, shifted by 8 it is < 2^24 (vs_div255's domain); c <= a.
//
// Synthesizable Verilog-2005, combinational.
module vs_separate_trilinear #(
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
    wire [8*(S+1)-1:0] w;
    vs_trilinear_weights #(.F(F)) weights (.fx(fx), .fy(fy), .fz(fz), .w(w));

    // Exact sums per channel k (0 = r, 1 = g, 2 = b, 3 = alpha) at sums[(S+8)*k +: S+8].
    reg [4*(S+8)-1:0] sums;
    reg [S+7:0]       acc;
    integer i, k;
    always @* begin
        sums = 0;
        acc = 0;
        for (k = 0; k < 4; k = k + 1) begin
            acc = 0;
            for (i = 0; i < 8; i = i + 1)
                acc = acc + w[(S+1)*i +: S+1] * voxels[32*i + 8*k +: 8];
            sums[(S+8)*k +: S+8] = acc;
        end
    end

    // U8.8 straight values (round half up): u[16*k +: 16], each <= 65280.
    wire [63:0] u;
    wire [47:0] cout;
    genvar k2;
    generate
        for (k2 = 0; k2 < 4; k2 = k2 + 1) begin : level
            wire [S+16:0] half = 1;
            wire [S+16:0] num = ({9'd0, sums[(S+8)*k2 +: S+8]} << 8) + (half << (S - 1));
            /* verilator lint_off UNUSEDSIGNAL */
            wire [S+16:0] q = num >> S; // <= 65280: the high bits are zero
            /* verilator lint_on UNUSEDSIGNAL */
            assign u[16*k2 +: 16] = q[15:0];
        end
        for (k2 = 0; k2 < 3; k2 = k2 + 1) begin : assoc
            // n[7:0] is divided away, c[16] is zero (c <= a): unused by design.
            /* verilator lint_off UNUSEDSIGNAL */
            wire [31:0] n = u[63:48] * u[16*k2 +: 16] + 32'd32640;
            wire [16:0] c;
            /* verilator lint_on UNUSEDSIGNAL */
            vs_div255 div (.x(n[31:8]), .q(c));
            assign cout[16*k2 +: 16] = c[15:0];
        end
    endgenerate
    assign r = cout[15:0];
    assign g = cout[31:16];
    assign b = cout[47:32];
    assign a = u[63:48];
endmodule
