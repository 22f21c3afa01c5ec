// vs_nearest_tap: the voxel nearest-neighbour sampling reads from one 2x2x2 tap set
// (volsample::fixed_point::nearest_index, round half up, at index 0 of each axis).
//
// Inputs
//   voxels : eight voxels of VW bits (default 32: u8 {a, b, g, r}); voxel i (corner
//            (i&1, (i>>1)&1, i>>2)) at voxels[VW*i +: VW]
//   fx, fy, fz : fractions of the position, F fractional bits each (4 <= F <= 12)
// Output
//   v : voxel i with i = bx + 2*by + 4*bz, where per axis b = floor(f/2^F + 1/2) = (f >= 2^(F-1)),
//       the fraction's top bit (round half up; index 1 is never clamped in a 2x2x2 set)
//
// Synthesizable Verilog-2005, combinational.
module vs_nearest_tap #(
    parameter F = 8,
    parameter VW = 32
) (
    input  wire [8*VW-1:0] voxels,
    input  wire [F-1:0] fx,
    input  wire [F-1:0] fy,
    input  wire [F-1:0] fz,
    output wire [VW-1:0] v
);
    wire [2:0] i = {fz[F-1], fy[F-1], fx[F-1]};
    assign v = voxels[VW*i +: VW];
endmodule
