// vs_trilinear_weights: the eight exact integer trilinear weights of one tap set
// (volsample::fixed_point::weights::trilinear_weights).
//
// Inputs  fx, fy, fz : fractions of the position, F fractional bits each (4 <= F <= 12)
// Outputs w : weight i (corner (i&1, (i>>1)&1, i>>2)) at w[(S+1)*i +: S+1], S = 3F
//
//   per axis  p0 = 2^F - f (low corner), p1 = f (high corner)
//   w_i       = px * py * pz          exact, no rounding; sum of the w_i = 2^S
// Widths: each factor <= 2^F (F+1 bits), so w_i <= 2^S (S+1 bits).
//
// Synthesizable Verilog-2005, combinational.
module vs_trilinear_weights #(
    parameter F = 8
) (
    input  wire [F-1:0]         fx,
    input  wire [F-1:0]         fy,
    input  wire [F-1:0]         fz,
    output wire [8*(3*F+1)-1:0] w
);
    localparam S = 3 * F;
    wire [F:0] one_f = 1 << F;
    wire [F:0] px0 = one_f - fx, px1 = {1'b0, fx};
    wire [F:0] py0 = one_f - fy, py1 = {1'b0, fy};
    wire [F:0] pz0 = one_f - fz, pz1 = {1'b0, fz};

    genvar i;
    generate
        for (i = 0; i < 8; i = i + 1) begin : corner
            wire [F:0] px = ((i & 1) != 0) ? px1 : px0;
            wire [F:0] py = ((i & 2) != 0) ? py1 : py0;
            wire [F:0] pz = ((i & 4) != 0) ? pz1 : pz0;
            // The product of three (F+1)-bit factors is at most 2^S: S+1 bits hold it.
            wire [S:0] wi = px * py * pz;
            assign w[(S+1)*i +: S+1] = wi;
        end
    endgenerate
endmodule
