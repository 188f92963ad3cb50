// subdiv — subdiv:N ([CS300-TexMap] "Optimization"; [Romanyuk-PCF] §4.4's
// piecewise approximation): the exact value at the nodes k = 0, N, 2N, …,
// n - 1 of a span and linear interpolation between them. One reciprocal
// per node, i.e. per N pixels: the node values come from exact's datapath
// (an instance of hw/rtl/exact_stages.v, exact.v's stages S1..S6), one
// node per clock, so the nodes of the following
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
    localparam LOGN = $clog2(N);
    localparam QW = $clog2(DEPTH);
    localparam PW = TOW + 1 + RB + 1;  // (t_b - t_a) * R[len]
    localparam AW = PW - RB + SF + 1;  // the interpolation accumulator

    // ------------------------------------------------------ table
    reg [RB:0] rtab [0:N];
    /* verilator lint_off UNUSEDSIGNAL */
    integer i, seed;
    /* verilator lint_on UNUSEDSIGNAL */
    initial begin
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

    // ------------------------------------------- S1..S6 (exact_stages.v)
    wire                  v6, ovf6;
    wire signed [TOW-1:0] tu6, tv6;
    exact_stages #(.EW(EW), .NW(NW), .SW(SW), .TOW(TOW)) stages (
        .clk(clk), .rst(rst), .in_valid(launch), .E(E), .Nu(Nu), .Nv(Nv),
        .out_valid(v6), .out_ovf(ovf6), .out_tu(tu6), .out_tv(tv6));
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
            out_valid <= 0;
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
            // beside S1..S6
            l1 <= lseg; z1 <= last_node; l2 <= l1; z2 <= z1; l3 <= l2; z3 <= z2;
            l4 <= l3; z4 <= z3; l5 <= l4; z5 <= z4; l6 <= l5; z6 <= z5;
            // queue
            if (v6) begin
                qu[wp] <= tu6; qv[wp] <= tv6; qo[wp] <= ovf6; ql[wp] <= l6; qz[wp] <= z6;
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
