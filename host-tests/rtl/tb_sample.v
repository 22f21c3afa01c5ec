// Test bench: the sampling datapaths other than vs_ow_trilinear against
// `volsample vectors --kernel <KERNEL>`, one bench for the five kernels with the same words:
//   KIND 0 opacity-weighted-nearest  vs_ow_nearest
//   KIND 1 separate-nearest          vs_separate_nearest
//   KIND 2 separate-trilinear        vs_separate_trilinear
//   KIND 3 preweighted-nearest       vs_preweighted_nearest
//   KIND 4 preweighted-trilinear     vs_preweighted_trilinear
// Input word: voxel i at bits 32*i +: 32 ({a, b, g, r}), then fx, fy, fz (F bits each) from
// bit 256; output word {a, b, g, r}, 16 bits each (the manifests' layouts).
// Plusargs: +INPUTS=<inputs.hex> +EXPECTED=<expected.hex>; parameters KIND, F and N (-P).
// Prints every mismatch (the first 20 in full) and one final line starting with "PASS:" or
// "FAIL:" (run.sh greps it).
module tb_sample;
    parameter KIND = 0;
    parameter F = 8;
    parameter N = 10000;
    localparam IW = 256 + 3 * F;

    reg [IW-1:0] in_mem  [0:N-1];
    reg [63:0]   exp_mem [0:N-1];
    reg [IW-1:0] in_w;
    wire [15:0]  r, g, b, a;
    wire [63:0]  got = {a, b, g, r};
    wire [255:0] vox = in_w[255:0];
    wire [F-1:0] fx = in_w[256 +: F], fy = in_w[256 + F +: F], fz = in_w[256 + 2 * F +: F];

    generate
        if (KIND == 0) begin : dut_ow_nearest
            vs_ow_nearest #(.F(F)) dut (.voxels(vox), .fx(fx), .fy(fy), .fz(fz), .r(r), .g(g), .b(b), .a(a));
        end else if (KIND == 1) begin : dut_separate_nearest
            vs_separate_nearest #(.F(F)) dut (.voxels(vox), .fx(fx), .fy(fy), .fz(fz), .r(r), .g(g), .b(b), .a(a));
        end else if (KIND == 2) begin : dut_separate_trilinear
            vs_separate_trilinear #(.F(F)) dut (.voxels(vox), .fx(fx), .fy(fy), .fz(fz), .r(r), .g(g), .b(b), .a(a));
        end else if (KIND == 3) begin : dut_preweighted_nearest
            vs_preweighted_nearest #(.F(F)) dut (.voxels(vox), .fx(fx), .fy(fy), .fz(fz), .r(r), .g(g), .b(b), .a(a));
        end else begin : dut_preweighted_trilinear
            vs_preweighted_trilinear #(.F(F)) dut (.voxels(vox), .fx(fx), .fy(fy), .fz(fz), .r(r), .g(g), .b(b), .a(a));
        end
    endgenerate

    reg [8*1024-1:0] in_file, exp_file;
    reg [8*32-1:0]   name;
    integer i, errors;
    initial begin
        case (KIND)
            0: name = "vs_ow_nearest";
            1: name = "vs_separate_nearest";
            2: name = "vs_separate_trilinear";
            3: name = "vs_preweighted_nearest";
            default: name = "vs_preweighted_trilinear";
        endcase
        if (!$value$plusargs("INPUTS=%s", in_file) || !$value$plusargs("EXPECTED=%s", exp_file)) begin
            $display("FAIL: tb_sample needs +INPUTS=<file> +EXPECTED=<file>");
            $finish;
        end
        $readmemh(in_file, in_mem);
        $readmemh(exp_file, exp_mem);
        errors = 0;
        in_w = 0;
        for (i = 0; i < N; i = i + 1) begin
            in_w = in_mem[i];
            #1;
            // !== also flags X/Z, e.g. words missing from a short file.
            if (got !== exp_mem[i]) begin
                errors = errors + 1;
                if (errors <= 20)
                    $display("MISMATCH vector %0d: got %h expected %h input %h", i, got, exp_mem[i], in_mem[i]);
            end
        end
        if (errors == 0)
            $display("PASS: %0s F=%0d: %0d vectors, 0 mismatches", name, F, N);
        else
            $display("FAIL: %0s F=%0d: %0d vectors, %0d mismatches", name, F, N, errors);
        $finish;
    end
endmodule
