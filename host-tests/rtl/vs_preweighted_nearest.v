// vs_preweighted_nearest: integer Preweighted nearest-neighbour sample of one 2x2x2 tap set
// (volsample::fixed_point::preweighted with the single weight 1, shift s = 0).
//
// Inputs  voxels (associated u8, {a, b~, g~, r~} per voxel), fx, fy, fz (F fractional
//         bits): as vs_preweighted_trilinear; the voxel read is vs_nearest_tap's.
// Outputs (U8.8; 65280 = opacity 1): r, g, b associated color C~, a opacity.
//
// Arithmetic (round half up at s = 0 is exact): a = 256*alpha,
//   c = 256*min(C~, alpha) (the min is a no-op for valid voxels, as in the Rust kernel).
//
// Synthesizable Verilog-2005, combinational.
module vs_preweighted_nearest #(
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
    wire [7:0] cr = (v[7:0] > al) ? al : v[7:0];
    wire [7:0] cg = (v[15:8] > al) ? al : v[15:8];
    wire [7:0] cb = (v[23:16] > al) ? al : v[23:16];
    assign r = {cr, 8'd0};
    assign g = {cg, 8'd0};
    assign b = {cb, 8'd0};
    assign a = {al, 8'd0};
endmodule
