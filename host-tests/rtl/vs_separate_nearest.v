// vs_separate_nearest: integer Separate nearest-neighbour sample of one 2x2x2 tap set
// (volsample::fixed_point::separate with the single weight 1, shift s = 0).
//
// Inputs  voxels (straight u8, {a, b, g, r} per voxel), fx, fy, fz (F fractional bits):
//         as vs_separate_trilinear; the voxel read is vs_nearest_tap's.
// Outputs (U8.8; 65280 = opacity 1): r, g, b associated color C~, a opacity.
//
// Arithmetic (as the Rust kernel at s = 0):
//   a = 256*alpha, C = 256*C_byte                       (round half up at s = 0: exact)
//   c = floor(a*C / 65280 + 1/2) = floor(((a*C + 32640) >> 8) / 255)   round half up
// Widths: a*C + 32640 < 2^32, shifted by 8 it is < 2^24 (vs_div255's domain); c <= a.
//
// Synthesizable Verilog-2005, combinational.
module vs_separate_nearest #(
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
    wire [15:0] a16 = {v[31:24], 8'd0};
    wire [47:0] c;
    genvar k;
    generate
        for (k = 0; k < 3; k = k + 1) begin : color
            // n[7:0] is divided away, q[16] is zero (q <= a): unused by design.
            /* verilator lint_off UNUSEDSIGNAL */
            wire [31:0] n = a16 * {v[8*k +: 8], 8'd0} + 32'd32640;
            wire [16:0] q;
            /* verilator lint_on UNUSEDSIGNAL */
            vs_div255 div (.x(n[31:8]), .q(q));
            assign c[16*k +: 16] = q[15:0];
        end
    endgenerate
    assign r = c[15:0];
    assign g = c[31:16];
    assign b = c[47:32];
    assign a = a16;
endmodule
