// Place-and-route tops for synth.sh (nextpnr-ice40 --up5k): an iCE40 UP5K package has far
// fewer pins than a datapath has port bits, so each top feeds its datapath from an input
// shift register (pin sin, one bit per clock) and captures the datapath's outputs in an
// output register (parallel load while pin load is high, else shifted out to pin sout).
// Every datapath port is therefore a register: the Fmax nextpnr reports for clk is that of
// the register-to-register paths through the datapath (combinational datapaths: input
// register -> datapath -> output register; vs_ow_ftb_lean: its own registers, its handshake
// inputs and outputs registered as well). These tops are for timing only; they are not
// simulated.
//
// Synthesizable Verilog-2005.

// vs_pnr_io: the shift-in register q (IW bits) and the shift-out register (OW bits).
module vs_pnr_io #(
    parameter IW = 8,
    parameter OW = 8
) (
    input  wire          clk,
    input  wire          sin,
    input  wire          load,
    output wire          sout,
    output reg  [IW-1:0] q,
    input  wire [OW-1:0] d
);
    reg [OW-1:0] o;
    always @(posedge clk) begin
        q <= {q[IW-2:0], sin};
        o <= load ? d : {o[OW-2:0], 1'b0};
    end
    assign sout = o[OW-1];
endmodule

module pnr_ow_nearest (
    input  wire clk,
    input  wire sin,
    input  wire load,
    output wire sout
);
    wire [279:0] q;
    wire [63:0]  d;
    vs_pnr_io #(.IW(280), .OW(64)) io (.clk(clk), .sin(sin), .load(load), .sout(sout), .q(q), .d(d));
    vs_ow_nearest #(.F(8)) dut (
        .voxels(q[255:0]), .fx(q[263:256]), .fy(q[271:264]), .fz(q[279:272]),
        .r(d[15:0]), .g(d[31:16]), .b(d[47:32]), .a(d[63:48])
    );
endmodule

module pnr_preweighted_nearest (
    input  wire clk,
    input  wire sin,
    input  wire load,
    output wire sout
);
    wire [279:0] q;
    wire [63:0]  d;
    vs_pnr_io #(.IW(280), .OW(64)) io (.clk(clk), .sin(sin), .load(load), .sout(sout), .q(q), .d(d));
    vs_preweighted_nearest #(.F(8)) dut (
        .voxels(q[255:0]), .fx(q[263:256]), .fy(q[271:264]), .fz(q[279:272]),
        .r(d[15:0]), .g(d[31:16]), .b(d[47:32]), .a(d[63:48])
    );
endmodule

module pnr_composite_ftb (
    input  wire clk,
    input  wire sin,
    input  wire load,
    output wire sout
);
    wire [127:0] q;
    wire [63:0]  d;
    vs_pnr_io #(.IW(128), .OW(64)) io (.clk(clk), .sin(sin), .load(load), .sout(sout), .q(q), .d(d));
    vs_composite_ftb dut (.acc(q[63:0]), .s(q[127:64]), .out(d));
endmodule

module pnr_ow_ftb_lean (
    input  wire clk,
    input  wire sin,
    input  wire load,
    output wire sout
);
    // q: voxels, fx, fy, fz, acc, then rst, in_valid, out_ready; d: s, out, in_ready, out_valid.
    wire [346:0] q;
    wire [129:0] d;
    vs_pnr_io #(.IW(347), .OW(130)) io (.clk(clk), .sin(sin), .load(load), .sout(sout), .q(q), .d(d));
    vs_ow_ftb_lean #(.F(8)) dut (
        .clk(clk), .rst(q[344]),
        .in_valid(q[345]), .in_ready(d[128]),
        .voxels(q[255:0]), .fx(q[263:256]), .fy(q[271:264]), .fz(q[279:272]), .acc(q[343:280]),
        .out_valid(d[129]), .out_ready(q[346]),
        .s(d[63:0]), .out(d[127:64])
    );
endmodule
