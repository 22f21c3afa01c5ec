// vs_opacity_correction: table-driven integer opacity correction of one U8.8 sample
// (volsample::fixed_point::correction::IntCorrection::apply):
// alpha_d = 1 - (1 - alpha)^r, C~_d = C~*alpha_d/alpha, r = d/d'.
//
// Inputs
//   s         : U8.8 sample {a, b, g, r} (r in bits 15:0), c <= a <= 65280
//   ratio_raw : r as U32.32, floor(r*2^32 + 1/2)
// Output
//   out       : corrected U8.8 sample {a_d, b_d, g_d, r_d}
// Tables (ROMs loaded with $readmemh; the files `volsample vectors --kernel
// opacity-correction` writes, entry j on line j; they do not depend on r):
//   PSI_HEX    G[j]   = floor(2^47*psi(128j/65280)/65280 + 1/2), psi(x) = -ln(1-x)/x, 257 x 32 bits
//   LN_M_HEX   Lam[j] = floor(2^32*ln(1 + j/256) + 1/2), 257 x 32 bits
//   LN_TOP_HEX K[e]   = floor(2^39*ln(65280/2^e) + 1/2), e = 0..14, 15 x 44 bits
//   PHI_HEX    Phi[j] = floor(2^31*phi(j/256) + 1/2), phi(x) = (1 - e^-x)/x, 257 x 32 bits
//   EXP_HEX    E[j]   = floor(2^31*e^(-j/256) + 1/2), 257 x 32 bits
//   EXP_INT_HEX X[n-1] = floor(2^32*e^(-n) + 1/2), n = 1..15, 15 x 32 bits
//
// Arithmetic (v = alpha raw; every rounding named, as the Rust kernel):
//   interp7(T, j) = T[j >> 7]*(128 - (j & 127)) + T[(j >> 7) + 1]*(j & 127)   exact, j < 2^15
//   1. v = 0: a_d = 0; v = 65280: a_d = 65280.
//   2. v < 2^15:  y = (r_raw*v*interp7(G, v) + 2^57) >> 58                   round half up
//   3. v >= 2^15: u = 65280 - v (1..32767), e = floor(log2 u), m = u*2^(15-e) - 2^15,
//                 L = max(K[e] - interp7(Lam, m), 0)                          (saturating)
//                 y = (r_raw*L + 2^42) >> 43                                  round half up
//      (y = r*L in units of 2^-28, L = -ln(1 - alpha) the optical depth)
//   4. y = min(y, 16*2^28)                                                    saturate
//      y < 2^28:  P = Phi[y >> 20]*(2^20 - f) + Phi[(y >> 20) + 1]*f, f = y mod 2^20   exact
//                 a_d = (65280*y*P + 2^78) >> 79                              round half up
//      y >= 2^28: n = y >> 28; Q = 0 if n = 16, else
//                 Q = X[n-1]*(E[t >> 20]*(2^20 - f) + E[(t >> 20) + 1]*f), t = y mod 2^28,
//                 f = t mod 2^20                                              exact
//                 a_d = (65280*(2^83 - min(Q, 2^83)) + 2^82) >> 83            round half up
//                 (Q < 2^82 by the widths below, so the min is a no-op here)
//   5. c_d = floor(c*a_d / v + 1/2) = floor((2*c*a_d + v) / (2*v))            round half up
//      (0 when v = 0)
// Widths: interp7 < 2^39; r_raw*v*interp7 < 2^118; K[e] < 2^43, r_raw*L < 2^107;
//   y before saturation < 2^65, after <= 2^32; P <= 2^51, 65280*y*P < 2^95;
//   Q < 2^82; 65280*2^83 < 2^99; a_d <= 65280; 2*c*a_d + v < 2^33; c_d <= a_d.
//
// Synthesizable Verilog-2005, combinational (asynchronous ROM reads; the three dividers
// by v are the expensive part).
module vs_opacity_correction #(
    parameter PSI_HEX     = "table_psi.hex",
    parameter LN_M_HEX    = "table_ln_m.hex",
    parameter LN_TOP_HEX  = "table_ln_top.hex",
    parameter PHI_HEX     = "table_phi.hex",
    parameter EXP_HEX     = "table_exp.hex",
    parameter EXP_INT_HEX = "table_exp_int.hex"
) (
    input  wire [63:0] s,
    input  wire [63:0] ratio_raw,
    output wire [63:0] out
);
    localparam [15:0] ONE = 16'd65280;

    reg [31:0] psi     [0:256];
    reg [31:0] ln_m    [0:256];
    reg [43:0] ln_top  [0:14];
    reg [31:0] phi     [0:256];
    reg [31:0] exp_t   [0:256];
    reg [31:0] exp_int [0:14];
    initial begin
        $readmemh(PSI_HEX, psi);
        $readmemh(LN_M_HEX, ln_m);
        $readmemh(LN_TOP_HEX, ln_top);
        $readmemh(PHI_HEX, phi);
        $readmemh(EXP_HEX, exp_t);
        $readmemh(EXP_INT_HEX, exp_int);
    end

    wire [15:0] v = s[63:48];

    // Step 2: the psi path (v < 2^15).
    wire [8:0]  pi0 = {1'b0, v[14:7]};
    wire [8:0]  pi1 = pi0 + 9'd1;
    wire [7:0]  pf  = {1'b0, v[6:0]};
    wire [7:0]  pfc = 8'd128 - pf;
    wire [38:0] pg  = psi[pi0] * pfc + psi[pi1] * pf;
    wire [118:0] y_psi_n = ratio_raw * v[14:0] * pg + (119'd1 << 57);
    /* verilator lint_off UNUSEDSIGNAL */
    wire [118:0] y_psi = y_psi_n >> 58;
    /* verilator lint_on UNUSEDSIGNAL */

    // Step 3: the ln m path (v >= 2^15).
    /* verilator lint_off UNUSEDSIGNAL */
    wire [15:0] u16 = ONE - v; // 1..32512 on this path: u16[15] is zero
    /* verilator lint_on UNUSEDSIGNAL */
    wire [14:0] u = u16[14:0];
    reg  [3:0]  e;
    integer b;
    always @* begin
        e = 0;
        for (b = 0; b < 15; b = b + 1)
            if (u[b])
                e = b[3:0];
    end
    /* verilator lint_off UNUSEDSIGNAL */
    wire [15:0] um = {1'b0, u} << (4'd15 - e); // in [2^15, 2^16)
    /* verilator lint_on UNUSEDSIGNAL */
    wire [14:0] m  = um[14:0];
    wire [8:0]  li0 = {1'b0, m[14:7]};
    wire [8:0]  li1 = li0 + 9'd1;
    wire [7:0]  lf  = {1'b0, m[6:0]};
    wire [7:0]  lfc = 8'd128 - lf;
    wire [38:0] lm  = ln_m[li0] * lfc + ln_m[li1] * lf;
    wire [43:0] top = ln_top[e];
    wire [43:0] l = (top > {5'd0, lm}) ? top - {5'd0, lm} : 44'd0;
    wire [108:0] y_ln_n = ratio_raw * l + (109'd1 << 42);
    /* verilator lint_off UNUSEDSIGNAL */
    wire [108:0] y_ln = y_ln_n >> 43;
    /* verilator lint_on UNUSEDSIGNAL */

    // Step 4: saturate y at 16*2^28, then phi (y < 1) or e^-y (1 <= y < 16).
    wire        psi_path = v < 16'd32768;
    wire        big = psi_path ? (y_psi >= (119'd1 << 32)) : (y_ln >= (109'd1 << 32));
    wire [32:0] y = big ? (33'd1 << 32) : (psi_path ? y_psi[32:0] : y_ln[32:0]);

    wire [8:0]  ti0 = {1'b0, y[27:20]};
    wire [8:0]  ti1 = ti0 + 9'd1;
    wire [20:0] tf = {1'b0, y[19:0]};
    wire [20:0] tf_c = 21'h100000 - tf;
    wire [50:0] p_phi = phi[ti0] * tf_c + phi[ti1] * tf;
    wire [50:0] p_exp = exp_t[ti0] * tf_c + exp_t[ti1] * tf;
    wire [4:0]  n = y[32:28];
    wire [3:0]  n1 = n[3:0] - 4'd1;
    wire [81:0] q = (n == 5'd0 || n == 5'd16) ? 82'd0 : exp_int[n1] * p_exp;

    wire [94:0]  a_phi_n = ONE * y[27:0] * p_phi + (95'd1 << 78);
    wire [99:0]  a_exp_n = ONE * ((100'd1 << 83) - {18'd0, q}) + (100'd1 << 82);
    /* verilator lint_off UNUSEDSIGNAL */
    wire [94:0]  a_phi = a_phi_n >> 79;
    wire [99:0]  a_exp = a_exp_n >> 83;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [15:0] a_mid = (n == 5'd0) ? a_phi[15:0] : a_exp[15:0];
    wire [15:0] a_d = (v == 16'd0) ? 16'd0 : (v >= ONE) ? ONE : a_mid;

    // Step 5: the colors, c_d = floor((2*c*a_d + v) / (2*v)).
    genvar k;
    generate
        for (k = 0; k < 3; k = k + 1) begin : color
            wire [31:0] prod = s[16*k +: 16] * a_d;
            wire [32:0] num = {prod, 1'b0} + {17'd0, v};
            wire [32:0] den = {16'd0, v, 1'b0};
            /* verilator lint_off UNUSEDSIGNAL */
            wire [32:0] quo = (v == 16'd0) ? 33'd0 : num / den; // <= a_d: 16 bits
            /* verilator lint_on UNUSEDSIGNAL */
            assign out[16*k +: 16] = quo[15:0];
        end
    endgenerate
    assign out[63:48] = a_d;
endmodule
