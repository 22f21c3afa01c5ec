// vs_preweighted_trilinear: integer Preweighted trilinear sample of one 2x2x2 tap set
// (volsample::fixed_point::preweighted, Drebin's interpolation of associated colors).
//
// Inputs
//   voxels : eight associated (premultiplied) u8 voxels; voxel i (corner (i&1, (i>>1)&1,
//            i>>2)) at voxels[32*i +: 32] = {a, b~, g~, r~} (r~ in the low byte)
//   fx, fy, fz : fractions of the position, F fractional bits each (4 <= F <= 12)
// Outputs (U8.8; 65280 = opacity 1)
//   r, g, b : associated color C~, a : opacity alpha
//
// Arithmetic (exact sums, one rounding per output, round half up, as in the Rust kernel):
//   w_i  = trilinear weights (vs_trilinear_weights), sum 2^S, S = 3F
//   S_a  = sum w_i * alpha_i
//   S_c  = sum w_i * min(C~_i, alpha_i)   per channel (the min is a no-op for valid voxels)
//   x    = floor(256*S_x / 2^S + 1/2) = (256*S_x + 2^(S-1)) >> S   for x in r, g, b, a
// Widths: S_x <= 255*2^S < 2^(S+8); 256*S_x + 2^(S-1) < 2^(S+16); outputs <= 65280.
//
// Synthesizable Verilog-2005, combinational.
module vs_preweighted_trilinear #(
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
    reg [7:0]         x, al;
    integer i, k;
    always @* begin
        sums = 0;
        acc = 0;
        x = 0;
        al = 0;
        for (k = 0; k < 4; k = k + 1) begin
            acc = 0;
            for (i = 0; i < 8; i = i + 1) begin
                x = voxels[32*i + 8*k +: 8];
                al = voxels[32*i + 24 +: 8];
                if (x > al)
                    x = al;
                acc = acc + w[(S+1)*i +: S+1] * x;
            end
            sums[(S+8)*k +: S+8] = acc;
        end
    end

    // U8.8 values, round half up: out[16*k +: 16], each <= 65280.
    wire [63:0] out;
    genvar k2;
    generate
        for (k2 = 0; k2 < 4; k2 = k2 + 1) begin : level
            wire [S+16:0] half = 1;
            wire [S+16:0] num = ({9'd0, sums[(S+8)*k2 +: S+8]} << 8) + (half << (S - 1));
            /* verilator lint_off UNUSEDSIGNAL */
            wire [S+16:0] q = num >> S; // <= 65280: the high bits are zero
            /* verilator lint_on UNUSEDSIGNAL */
            assign out[16*k2 +: 16] = q[15:0];
        end
    endgenerate
    assign r = out[15:0];
    assign g = out[31:16];
    assign b = out[47:32];
    assign a = out[63:48];
endmodule
