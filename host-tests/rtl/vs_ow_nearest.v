// vs_ow_nearest: integer OpacityWeighted nearest-neighbour sample of one 2x2x2 tap set
// (volsample::fixed_point::opacity_weighted with the single weight 1, shift s = 0).
//
// Inputs  voxels (straight u8, {a, b, g, r} per voxel), fx, fy, fz (F fractional bits):
//         as vs_ow_trilinear; the voxel read is vs_nearest_tap's.
// Outputs (U8.8; 65280 = opacity 1): r, g, b associated color C~, a opacity.
//
// Arithmetic (one rounding per color, round half up, as the Rust kernel at s = 0):
//   a = floor(256*alpha / 2^0 + 1/2) = 256*alpha                                 (exact)
//   c = floor(256*alpha*C / 255 + 1/2) = floor((512*alpha*C + 255) / 510)
//     = floor((256*alpha*C + 127) / 255)                                    (nested floors)
// Widths: 256*alpha*C + 127 <= 255*255*256 + 127 < 2^24 (vs_div255's domain); c <= a.
//
// Synthesizable Verilog-2005, combinational.
module vs_ow_nearest #(
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
    wire [31:0] v;
    vs_nearest_tap #(.F(F)) tap (.voxels(voxels), .fx(fx), .fy(fy), .fz(fz), .v(v));
    wire [7:0] al = v[31:24];
    wire [47:0] c;
    genvar k;
    generate
        for (k = 0; k < 3; k = k + 1) begin : color
            wire [15:0] p = al * v[8*k +: 8];
            wire [23:0] n = {p, 8'd127}; // 256*alpha*C + 127
            /* verilator lint_off UNUSEDSIGNAL */
            wire [16:0] q; // q[16] is zero (q <= a)
            /* verilator lint_on UNUSEDSIGNAL */
            vs_div255 div (.x(n), .q(q));
            assign c[16*k +: 16] = q[15:0];
        end
    endgenerate
    assign r = c[15:0];
    assign g = c[31:16];
    assign b = c[47:32];
    assign a = {al, 8'd0};
endmodule
