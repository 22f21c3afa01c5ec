// vs_ow_ftb_lean: resource-lean OpacityWeighted trilinear sample + front-to-back step, the
// arithmetic of vs_ow_ftb_pipe (bit-identical outputs) computed over many clocks with a few
// shared multipliers, so that it fits a small FPGA (an iCE40 UP5K at F = 8: see README.md).
// Parameter F (4..12).
//
// Ports: the same data as vs_ow_ftb_pipe (voxels: eight straight u8 voxels, voxel i = corner
// (i&1, (i>>1)&1, i>>2) at voxels[32*i +: 32] = {a, b, g, r}; fx, fy, fz with F fractional
// bits; acc: the U8.8 accumulator {a, b, g, r} in front of the sample), with valid/ready
// handshakes on both sides: a sample is taken on a clock edge with in_valid && in_ready;
// s (= vs_ow_trilinear's sample) and out (= vs_composite_ftb's front_to_back(acc, s)) are
// held with out_valid until a clock edge with out_ready. in_ready = idle, or done with
// out_ready (a new sample can be taken on the edge that hands the last one over).
//
// Timing: out_valid rises on the 43rd clock edge after the edge that takes the sample, so the
// result can be handed over on the 44th (LATENCY = 44 clocks), and the next sample is taken
// on that same edge: with out_ready held high, one sample every 44 clocks.
//
// Schedule (step = 0..42 in the clocks after the accepting edge; each stage ends in a
// register):
//   steps 0..31, one product per clock, tap i = step[4:2], channel k = step[1:0]
//   (0..2 = r, g, b; 3 = alpha); stages of a 4-deep pipe:
//     A: pxy = px*py (F+1 by F+1 bits); m = alpha_i (k = 3) or alpha_i*C_ik (8 by 8 bits)
//     B: w_i = pxy*pz (2F+2 by F+1 bits; exact, S+1 bits, S = 3F)
//     C: p = w_i*m (the shared product, max(S+1,16) by 16 bits): omega_i or omega_i*C_ik
//     D: S_a += p (k = 3) or S_c[k] += p (exact sums, S+8 and S+16 bits)
//   (w_i is formed again for every channel: the pipe is full anyway, and it saves storing it)
//   steps 35..38, channel k = step - 35: the sample's numerators (vs_ow_trilinear's
//     rounding, one per output): a = (256*S_a + 2^(S-1)) >> S,
//     q = (512*S_c + 255*2^S) >> (S+1)
//   steps 36..39: c = floor(q / 255) (round half up overall): the sample s_k
//   steps 37..40: the shared product again: T*s_k, T = 65280 - acc_a
//   steps 38..41: n = (T*s_k + 32640) >> 8
//   steps 39..42: out_k = acc_k + floor(n / 255)              (round half up overall)
// Multipliers: the four above (px*py, alpha*C, pxy*pz, the shared one); the divisions by
// 255 (floor(x/255) = (x*16843010) >> 32 for x < 2^24, vs_div255's exact multiply-shift)
// are written as shifts and adds (16843010 = 2^24 + 2^16 + 2^8 + 2), so they take no
// multiplier. Widths are vs_ow_trilinear's and vs_composite_ftb's (proofs in their headers).
// rst (synchronous, active high) returns to idle and drops out_valid.
//
// Synthesizable Verilog-2005.
module vs_ow_ftb_lean #(
    parameter F = 8
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         in_valid,
    output wire         in_ready,
    input  wire [255:0] voxels,
    input  wire [F-1:0] fx,
    input  wire [F-1:0] fy,
    input  wire [F-1:0] fz,
    input  wire [63:0]  acc,
    output wire         out_valid,
    input  wire         out_ready,
    output wire [63:0]  s,
    output wire [63:0]  out
);
    localparam S = 3 * F;
    localparam AW = (S + 1 > 16) ? S + 1 : 16; // the shared multiplier's first operand
    localparam [5:0] LAST = 6'd42;
    localparam [15:0] ONE = 16'd65280;

    // floor(x / 255) for x < 2^24: (x * 16843010) >> 32 as a sum of shifts.
    /* verilator lint_off UNUSEDSIGNAL */
    function [16:0] div255;
        input [23:0] x;
        reg [48:0] p;
        begin
            p = ({25'd0, x} << 24) + ({25'd0, x} << 16) + ({25'd0, x} << 8) + ({25'd0, x} << 1);
            div255 = p[48:32];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */

    // Control: idle (!busy, !done), busy (steps 0..LAST), done (out_valid).
    reg       busy, done;
    reg [5:0] step;
    assign in_ready = !busy && (!done || out_ready);
    assign out_valid = done;
    wire take = in_valid && in_ready;
    always @(posedge clk) begin
        if (rst) begin
            busy <= 1'b0;
            done <= 1'b0;
            step <= 6'd0;
        end else if (take) begin
            busy <= 1'b1;
            done <= 1'b0;
            step <= 6'd0;
        end else if (busy) begin
            if (step == LAST) begin
                busy <= 1'b0;
                done <= 1'b1;
            end
            step <= step + 6'd1;
        end else if (done && out_ready) begin
            done <= 1'b0;
        end
    end

    reg [255:0] vox;
    reg [F-1:0] fxr, fyr, fzr;
    reg [63:0]  accr;
    always @(posedge clk) begin
        if (take) begin
            vox <= voxels;
            fxr <= fx;
            fyr <= fy;
            fzr <= fz;
            accr <= acc;
        end
    end

    // Stage A: tap factors and the voxel operand.
    wire       issue = busy && !step[5];
    wire [2:0] ti = step[4:2];
    wire [1:0] tk = step[1:0];
    wire [F:0] one_f = 1 << F;
    wire [F:0] px = ti[0] ? {1'b0, fxr} : one_f - {1'b0, fxr};
    wire [F:0] py = ti[1] ? {1'b0, fyr} : one_f - {1'b0, fyr};
    wire [F:0] pz = ti[2] ? {1'b0, fzr} : one_f - {1'b0, fzr};
    wire [7:0] alpha = vox[{ti, 5'd24} +: 8];
    wire [7:0] chan = vox[{ti, tk, 3'd0} +: 8]; // byte k of voxel i
    reg  [2*F+1:0] pxy_a;
    reg  [F:0]     pz_a;
    reg  [15:0]    m_a, m_b;
    reg  [1:0]     k_a, k_b, k_c;
    reg            v_a, v_b, v_c;
    always @(posedge clk) begin
        pxy_a <= px * py;
        pz_a <= pz;
        m_a <= (tk == 2'd3) ? {8'd0, alpha} : alpha * chan;
        k_a <= tk;
        v_a <= issue && !rst;
    end

    // Stage B: the weight.
    reg [S:0] w_b;
    always @(posedge clk) begin
        w_b <= pxy_a * pz_a;
        m_b <= m_a;
        k_b <= k_a;
        v_b <= v_a && !rst;
    end

    // Stage C: the shared product (w_i*m while summing, T*s_k while compositing).
    reg            fin1, fin2;
    reg  [15:0]    s_f;
    wire [15:0]    t = ONE - accr[63:48];
    wire [AW-1:0]  mul_a = fin2 ? {{(AW-16){1'b0}}, s_f} : {{(AW-S-1){1'b0}}, w_b};
    wire [15:0]    mul_b = fin2 ? t : m_b;
    // (its top bit is zero at F > 4: w*m < 2^(S+16) and T*s < 2^32)
    /* verilator lint_off UNUSEDSIGNAL */
    reg  [AW+15:0] p_c;
    /* verilator lint_on UNUSEDSIGNAL */
    always @(posedge clk) begin
        p_c <= mul_a * mul_b;
        k_c <= k_b;
        v_c <= v_b && !rst;
    end

    // Stage D: exact sums (cleared when a sample is taken).
    reg [S+7:0]  sum_a;
    reg [S+15:0] sum_r, sum_g, sum_b;
    always @(posedge clk) begin
        if (take) begin
            sum_a <= 0;
            sum_r <= 0;
            sum_g <= 0;
            sum_b <= 0;
        end else if (v_c) begin
            case (k_c)
                2'd0: sum_r <= sum_r + p_c[S+15:0];
                2'd1: sum_g <= sum_g + p_c[S+15:0];
                2'd2: sum_b <= sum_b + p_c[S+15:0];
                default: sum_a <= sum_a + p_c[S+7:0];
            endcase
        end
    end

    // Rounding of the sample, one channel per clock: steps 35..38 the numerators' shifts
    // (q_f), 36..39 the division by 255 (the sample s_k), 37..40 the product T*s_k (p_c),
    // 38..41 (T*s_k + 32640) >> 8 (n_f), 39..42 the sum acc_k + n_f div 255.
    wire          fin0 = busy && (step >= 6'd35) && (step <= 6'd38);
    // The high bits of fstep, a_q, q, n and the quotients are zero (the width proofs): unused.
    /* verilator lint_off UNUSEDSIGNAL */
    wire [5:0]    fstep = step - 6'd35;
    wire [1:0]    fk = fstep[1:0];
    wire [S+15:0] sum_c = (fk == 2'd0) ? sum_r : (fk == 2'd1) ? sum_g : sum_b;
    wire [S+16:0] one_a = 1;
    wire [S+16:0] a_q = (({9'd0, sum_a} << 8) + (one_a << (S - 1))) >> S;
    wire [S+25:0] half_c = 255;
    wire [S+25:0] q = (({10'd0, sum_c} << 9) + (half_c << S)) >> (S + 1);
    wire [16:0]   c = div255(q_f);
    wire [31:0]   n = p_c[31:0] + 32'd32640;
    wire [16:0]   inc = div255(n_f);
    /* verilator lint_on UNUSEDSIGNAL */
    reg  [23:0]   q_f, n_f;
    reg           is_a;
    reg  [1:0]    k_f1, k_f2, k_f3, k_f4;
    reg           fin3, fin4;
    reg  [63:0]   s_r, out_r;
    wire [15:0]   s_k = is_a ? q_f[15:0] : c[15:0];
    always @(posedge clk) begin
        fin1 <= fin0 && !rst;
        fin2 <= fin1 && !rst;
        fin3 <= fin2 && !rst;
        fin4 <= fin3 && !rst;
        k_f1 <= fk;
        k_f2 <= k_f1;
        k_f3 <= k_f2;
        k_f4 <= k_f3;
        if (fin0) begin
            q_f <= (fk == 2'd3) ? {8'd0, a_q[15:0]} : q[23:0];
            is_a <= fk == 2'd3;
        end
        if (fin1) begin
            s_f <= s_k;
            s_r[16*k_f1 +: 16] <= s_k;
        end
        if (fin3)
            n_f <= n[31:8];
        if (fin4)
            out_r[16*k_f4 +: 16] <= accr[16*k_f4 +: 16] + inc[15:0];
    end
    assign s = s_r;
    assign out = out_r;
endmodule
