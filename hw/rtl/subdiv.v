// subdiv — subdiv:N ([CS300-TexMap] "Optimization"; [Romanyuk-PCF] §4.4's
// piecewise approximation): the exact value at the nodes k = 0, N, 2N, …,
// n - 1 of a span and linear interpolation between them. One reciprocal
// per node, i.e. per N pixels: the node values come from exact's datapath
// (hw/rtl/exact.v's stages S1..S6, copied here because the flow reads one
// file per module), one node per clock, so the nodes of the following
// segments and spans are computed while the pixels of the current one go
// out. Bit-exact with persp__hw_subdiv_span (src/analysis/hw_models_span.c;
// the format is in docs/HARDWARE.md, "subdiv").
//
//   launch  E, N2 at the next node (+ 2G·N per node, the span's end values
//           for the last node), one node per clock while the node queue
//           has room (DEPTH nodes in flight and queued);
//   S1..S6  exact's normalisation, seed, Newton step, t = Ns·r1 >>> 23;
//   queue   DEPTH node values with their segment length and last flag;
//   segment each node starts a segment: its own value, then len - 1
//           pixels t_a + floor(i·S / 2^SF), S = (t_b - t_a)·R[len] >>> (RB - SF)
//           summed (R[len] = round(2^RB / len), a shift for len = N); the
//           span's last node is a segment of one pixel.
//
// One pixel per clock while the queue holds the next segment's two nodes;
// interface as exact's, plus the span's end values (E1, Nu1, Nv1 = the
// start values + (len - 1) steps, from set-up). out_ovf: an end node of the
// pixel's segment has |t| >= 2^15 texels (t not meaningful).
module subdiv #(
    parameter N     = 16,  // node spacing, a power of two, 2..32
    parameter EW    = 41,
    parameter NW    = 56,
    parameter SW    = 32,
    parameter TOW   = 25,
    parameter LW    = 7,
    parameter RB    = 24,  // R[len] = round(2^RB / len)
    parameter SF    = 16,  // fraction bits of the interpolation
    parameter DEPTH = 16   // nodes in flight + queued (a power of two)
) (
    input  wire                 clk,
    input  wire                 rst,
    input  wire                 load,
    input  wire signed [EW-1:0] E0,
    input  wire signed [EW-1:0] G2,
    input  wire signed [NW-1:0] Nu0,
    input  wire signed [NW-1:0] Nv0,
    input  wire signed [NW-1:0] Au2,
    input  wire signed [NW-1:0] Av2,
    input  wire signed [EW-1:0] E1,
    input  wire signed [NW-1:0] Nu1,
    input  wire signed [NW-1:0] Nv1,
    input  wire        [LW-1:0] len,
    output wire                 ready,
    output reg                  out_valid,
    output reg                  out_ovf,
    output reg  signed [TOW-1:0] out_tu,
    output reg  signed [TOW-1:0] out_tv
);
    localparam MB = EW - 1;
    localparam SH = NW - SW;
    localparam LOGN = $clog2(N);
    localparam QW = $clog2(DEPTH);
    localparam PW = TOW + 1 + RB + 1;  // (t_b - t_a) * R[len]
    localparam AW = PW - RB + SF + 1;  // the interpolation accumulator

    // ------------------------------------------------------ tables
    reg [15:0] rom [0:255];
    reg [RB:0] rtab [0:N];
    /* verilator lint_off UNUSEDSIGNAL */
    integer i, seed;
    /* verilator lint_on UNUSEDSIGNAL */
    initial begin
        for (i = 0; i < 256; i = i + 1) begin
            seed = 33554432 / (513 + 2 * i);  // exact's seed: 2^24 / (256.5 + i)
            rom[i] = seed[15:0];
        end
        rtab[0] = 0;
        for (i = 1; i <= N; i = i + 1) begin
            seed = ((1 << RB) + i / 2) / i;
            rtab[i] = seed[RB:0];
        end
    end

    // ------------------------------------------------------ launch
    reg signed [EW-1:0] E, E1r, G2N;
    reg signed [NW-1:0] Nu, Nv, Nu1r, Nv1r, Au2N, Av2N;
    reg        [LW-1:0] rem;   // pixels from the next node to the span's end
    reg        [LOGN:0] lseg;  // the segment that ends at the next node
    reg                 act;
    reg        [QW:0]   cnt;   // nodes launched and not yet taken by a segment
    wire launch = act && cnt < DEPTH;
    wire last_node = rem == 0;
    wire take;                 // a segment starts: one node leaves the queue
    assign ready = !act || (launch && last_node);

    // ------------------------------------------------ S1..S6 (exact.v)
    reg [5:0] lz_c;
    integer k;
    always @* begin
        lz_c = 6'd0;
        for (k = 0; k < MB; k = k + 1)
            if (E[k]) lz_c = MB[5:0] - 6'd1 - k[5:0];
    end
    /* verilator lint_off UNUSEDSIGNAL */
    reg        [MB-1:0] m1;
    /* verilator lint_on UNUSEDSIGNAL */
    reg        [5:0]    lz1;
    reg signed [NW-1:0] Nu1s, Nv1s;
    reg                 v1;
    wire signed [NW+MB-1:0] shu = $signed({{MB{Nu1s[NW-1]}}, Nu1s}) <<< lz1;
    wire signed [NW+MB-1:0] shv = $signed({{MB{Nv1s[NW-1]}}, Nv1s}) <<< lz1;
    wire ovf_u = shu[NW+MB-1:NW-1] != {(MB+1){shu[NW-1]}};
    wire ovf_v = shv[NW+MB-1:NW-1] != {(MB+1){shv[NW-1]}};
    reg        [15:0]   r0_2, m16_2;
    reg signed [SW-1:0] Nsu2, Nsv2;
    reg                 ovf2, v2;
    reg        [31:0]   p3;
    reg        [15:0]   r0_3, r0_4;
    reg signed [SW-1:0] Nsu3, Nsv3, Nsu4, Nsv4, Nsu5, Nsv5, Nsu6, Nsv6;
    reg                 ovf3, ovf4, ovf5, ovf6, v3, v4, v5, v6;
    wire signed [32:0]  d  = $signed({1'b0, p3}) - 33'sd2147483648;
    /* verilator lint_off UNUSEDSIGNAL */
    wire signed [32:0]  d8w = d >>> 8;
    /* verilator lint_on UNUSEDSIGNAL */
    reg signed [31:0]   c4;
    /* verilator lint_off UNUSEDSIGNAL */
    wire signed [31:0]  cs = c4 >>> 22;
    wire signed [17:0]  r1w = $signed({2'b00, r0_4}) - cs[17:0];
    wire        [15:0]  r1 = r1w > 18'sd65535 ? 16'd65535 : (r1w < 18'sd32768 ? 16'd32768 : r1w[15:0]);
    /* verilator lint_on UNUSEDSIGNAL */
    reg         [14:0]  rr5;
    reg signed [SW+16:0] pu6, pv6;
    /* verilator lint_off UNUSEDSIGNAL */
    wire signed [SW+16:0] su = $signed({{2{Nsu6[SW-1]}}, Nsu6, 15'd0}) + pu6;
    wire signed [SW+16:0] sv = $signed({{2{Nsv6[SW-1]}}, Nsv6, 15'd0}) + pv6;
    /* verilator lint_on UNUSEDSIGNAL */
    // Each node's segment length and last flag travel with it.
    reg [LOGN:0] l1, l2, l3, l4, l5, l6;
    reg          z1, z2, z3, z4, z5, z6;

    // ------------------------------------------------------ node queue
    reg signed [TOW-1:0] qu [0:DEPTH-1];
    reg signed [TOW-1:0] qv [0:DEPTH-1];
    reg        [LOGN:0]  ql [0:DEPTH-1];
    reg                  qo [0:DEPTH-1];
    reg                  qz [0:DEPTH-1];
    reg        [QW-1:0]  wp, rp;
    reg        [QW:0]    qn;  // entries
    wire [QW-1:0] rp1 = rp + 1'b1;
    wire head_last = qz[rp];

    // ------------------------------------------------------ segment
    reg signed [AW-1:0] accu, accv, Su, Sv;
    reg        [LOGN:0] bl, j;
    reg                 bovf;
    wire cont = j < bl;
    assign take = !cont && qn != 0 && (head_last || qn > 1);
    wire signed [TOW:0] Du = $signed({qu[rp1][TOW-1], qu[rp1]}) - $signed({qu[rp][TOW-1], qu[rp]});
    wire signed [TOW:0] Dv = $signed({qv[rp1][TOW-1], qv[rp1]}) - $signed({qv[rp][TOW-1], qv[rp]});
    wire signed [RB+1:0] Rl = $signed({1'b0, rtab[ql[rp1]]});
    /* verilator lint_off UNUSEDSIGNAL */
    wire signed [PW-1:0] Pu = Du * Rl;
    wire signed [PW-1:0] Pv = Dv * Rl;
    /* verilator lint_on UNUSEDSIGNAL */
    wire signed [AW-1:0] nu = accu + Su;
    wire signed [AW-1:0] nv = accv + Sv;

    always @(posedge clk) begin
        if (rst) begin
            act <= 0; cnt <= 0; wp <= 0; rp <= 0; qn <= 0; bl <= 0; j <= 0;
            v1 <= 0; v2 <= 0; v3 <= 0; v4 <= 0; v5 <= 0; v6 <= 0; out_valid <= 0;
        end else begin
            // launch
            if (load) begin
                act <= 1'b1; E <= E0; Nu <= Nu0; Nv <= Nv0; E1r <= E1; Nu1r <= Nu1; Nv1r <= Nv1;
                G2N <= G2 <<< LOGN; Au2N <= Au2 <<< LOGN; Av2N <= Av2 <<< LOGN;
                rem <= len - 1'b1; lseg <= 0;
            end else if (launch) begin
                if (last_node) act <= 1'b0;
                else if (rem > N[LW-1:0]) begin
                    E <= E + G2N; Nu <= Nu + Au2N; Nv <= Nv + Av2N;
                    rem <= rem - N[LW-1:0]; lseg <= N[LOGN:0];
                end else begin
                    E <= E1r; Nu <= Nu1r; Nv <= Nv1r;
                    rem <= 0; lseg <= rem[LOGN:0];
                end
            end
            cnt <= cnt + {{QW{1'b0}}, launch} - {{QW{1'b0}}, take};
            // S1..S6
            v1 <= launch; lz1 <= lz_c; m1 <= E[MB-1:0] << lz_c; Nu1s <= Nu; Nv1s <= Nv;
            l1 <= lseg; z1 <= last_node;
            v2 <= v1; r0_2 <= rom[m1[MB-2:MB-9]]; m16_2 <= m1[MB-1:MB-16];
            Nsu2 <= shu[SW+SH-1:SH]; Nsv2 <= shv[SW+SH-1:SH]; ovf2 <= ovf_u || ovf_v; l2 <= l1; z2 <= z1;
            v3 <= v2; p3 <= m16_2 * r0_2; r0_3 <= r0_2; Nsu3 <= Nsu2; Nsv3 <= Nsv2; ovf3 <= ovf2;
            l3 <= l2; z3 <= z2;
            v4 <= v3; c4 <= $signed({1'b0, r0_3[15:1]}) * $signed(d8w[15:0]); r0_4 <= r0_3;
            Nsu4 <= Nsu3; Nsv4 <= Nsv3; ovf4 <= ovf3; l4 <= l3; z4 <= z3;
            v5 <= v4; rr5 <= r1[14:0]; Nsu5 <= Nsu4; Nsv5 <= Nsv4; ovf5 <= ovf4; l5 <= l4; z5 <= z4;
            v6 <= v5; pu6 <= Nsu5 * $signed({1'b0, rr5}); pv6 <= Nsv5 * $signed({1'b0, rr5});
            Nsu6 <= Nsu5; Nsv6 <= Nsv5; ovf6 <= ovf5; l6 <= l5; z6 <= z5;
            // queue
            if (v6) begin
                qu[wp] <= su[TOW+22:23]; qv[wp] <= sv[TOW+22:23]; qo[wp] <= ovf6; ql[wp] <= l6; qz[wp] <= z6;
                wp <= wp + 1'b1;
            end
            if (take) rp <= rp1;
            qn <= qn + {{QW{1'b0}}, v6} - {{QW{1'b0}}, take};
            // segment
            out_valid <= cont || take;
            if (cont) begin
                accu <= nu; accv <= nv; j <= j + 1'b1;
                out_tu <= nu[SF+TOW-1:SF]; out_tv <= nv[SF+TOW-1:SF]; out_ovf <= bovf;
            end else if (take) begin
                accu <= {{(AW-TOW-SF){qu[rp][TOW-1]}}, qu[rp], {SF{1'b0}}};
                accv <= {{(AW-TOW-SF){qv[rp][TOW-1]}}, qv[rp], {SF{1'b0}}};
                Su <= {Pu[PW-1], Pu[PW-1:RB-SF]}; Sv <= {Pv[PW-1], Pv[PW-1:RB-SF]};
                out_tu <= qu[rp]; out_tv <= qv[rp];
                out_ovf <= qo[rp] || (!head_last && qo[rp1]);
                bovf <= qo[rp] || (!head_last && qo[rp1]);
                bl <= head_last ? 1 : ql[rp1]; j <= 1;
            end
        end
    end
endmodule
