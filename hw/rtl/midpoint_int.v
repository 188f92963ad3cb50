// midpoint_int — the division-free per-pixel search of midpoint:int, one
// texture coordinate per instance ([Romanyuk-PCF] §4.5, (4.13)-(4.15); the
// fixed-point model and register widths of docs/METHODS.md, "Fixed-point
// model"). Bit-exact with persp's integer model (src/interp/midpoint.c,
// mp_span_fixed): per pixel E += 2G, W += T - K, then lattice steps
// W +-= 2E, T +-= 4G, n +-= 1 until 0 < W <= 2E, at most CAP steps; past the
// cap the index is re-seeded by an exact floor division (a sequential
// restoring divider here), and an index reaching |n| >= 2^NLIM ends the
// span's integer path (out_oor: persp finishes it in double precision).
//
// STEPS lattice steps per clock. j steps have the closed forms
// W +- 2jE, T +- 4jG, n +- j, and the search is monotone (all steps up when
// W <= 0, all down when W > 2E), so the first accepted j of 0..STEPS is the
// first of STEPS + 1 parallel compares: up, W + 2jE > 0; down,
// W - 2(j+1)E <= 0 (docs/HARDWARE.md). The accepted pixel's step to the
// next pixel (E + 2G, W + T - K) is taken in the same clock, so a pixel of
// s steps costs max(1, ceil(s / STEPS)) clocks. The register holds W - 1,
// which makes the direction and every test a sign bit, and each candidate
// forms its next-pixel W beside its test, so that the W -> W loop passes
// one carry chain and a select. A pixel needing more than
// CAP steps (W + 2·CAP·E <= 0, or W - 2(CAP+1)E > 0) goes to the re-seed at
// once: its outcome does not depend on the steps the model takes first.
//
// FALLBACK = 0: a pixel of more than STEPS steps stalls the span, and a
// re-seed runs a sequential divider (19 clocks). FALLBACK = 1: one pixel per
// clock on every pixel. The searched index is unique, n = floor_div(2*N2 +
// (1 - 2o)*E, 2E), the re-seed's formula, and N2, E are linear in x, so a
// pipelined divider fed from the span's start runs NLIM + 2 clocks ahead of
// the search and supplies n, W and T - K for the span's first pixel and for
// every pixel that the search does not finish within STEPS steps
// (docs/HARDWARE.md, "midpoint_int"). FALLBACK = 2: that divider alone.
//
// Interface: `load` (accepted whenever asserted; it aborts a span in
// progress, with FALLBACK 1, 2 the pixels not yet issued) latches the span's start values and len, the number of pixels
// to deliver; `ready` says that a load in this cycle loses nothing (idle, or
// this cycle accepts the span's last pixel; FALLBACK 1, 2: the span stage
// issues it). out_valid for one cycle per
// delivered pixel, registered; out_oor marks the pixel at which the integer
// path ends (out_n, out_W are then not meaningful) and the span stops there.
module midpoint_int #(
    parameter EW    = 43,  // E = G*X2 + H*Y2 + 2I > 0
    parameter N2W   = 59,  // N2 = A*X2 + B*Y2 + 2C, and A
    parameter WW    = 62,  // W, and T - K
    parameter TW    = 60,  // T = 2G*M
    parameter KW    = 61,  // K = 4A - 2G
    parameter NW    = 18,  // lattice index n (|n| < 2^NLIM plus the last clock's steps)
    parameter NLIM  = 16,  // the format's texel range: |n| < 2^NLIM
    parameter CAP   = 32,  // lattice steps before a re-seed
    parameter LW    = 7,   // span length counter (spans are at most 64 pixels)
    parameter STEPS = 1,   // lattice steps searched per clock, 1 <= STEPS <= CAP, < 31
    parameter FALLBACK = 1 // 0: stall for the extra steps and re-seeds; 1: run-ahead divider;
                           // 2: the divider alone (no search; STEPS unused)
) (
    input  wire                  clk,
    input  wire                  rst,
    input  wire                  load,
    input  wire                  o2,     // 2o: 1 texel centres, 0 texel edges
    input  wire signed [EW-1:0]  G,
    input  wire signed [N2W-1:0] A,
    input  wire signed [EW-1:0]  E0,
    input  wire signed [N2W-1:0] N2_0,
    // The search's start (FALLBACK 0; FALLBACK 1 takes the divider's).
    /* verilator lint_off UNUSEDSIGNAL */
    input  wire signed [NW-1:0]  n0,
    input  wire signed [WW-1:0]  W0,
    input  wire signed [TW-1:0]  T0,
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire signed [KW-1:0]  K,
    input  wire        [LW-1:0]  len,
    output wire                  ready,
    output reg                   out_valid,
    output reg                   out_oor,
    output reg                   out_reseed,
    output reg  signed [NW-1:0]  out_n,
    output reg  signed [WW-1:0]  out_W
);
    // Width of the re-seed's dividend |2*N2 + (1 - 2o)*E| (and of 2E << NLIM).
    localparam DW = N2W + 1;
    // The candidates W +- 2jE: one bit over W, so that a candidate beyond
    // the accepted one cannot wrap.
    localparam XW = WW + 1;
    localparam P  = STEPS;
    // Multiples 2jE and 4jG that are not shifts are registers (j <= 31).
    localparam MW = EW + 6, GW = EW + 7, DRW = EW + 9;

    // The search's registers: E, G and D = 2E + 4G of the pixel searched
    // (FALLBACK 1: of the pixel that leaves the divider pipeline), and the
    // state carried from pixel to pixel.
    reg signed [EW-1:0]  E, Gr;
    reg signed [WW-1:0]  Wb;  // W - 1: W <= 0 and every acceptance is then a sign bit
    reg signed [WW-1:0]  R;   // T - K: the pixel step is W += R
    reg signed [EW+2:0]  D;   // 2E + 4G: W + R moves by D per lattice step
    reg signed [NW-1:0]  n;

    // Used only where a multiple of E is a register (STEPS >= 2).
    /* verilator lint_off UNUSEDSIGNAL */
    wire ld = load && !rst;
    wire signed [XW-1:0] E0x = {{(XW-EW){E0[EW-1]}}, E0};
    wire signed [XW-1:0] G0x = {{(XW-EW){G[EW-1]}}, G};
    wire signed [XW-1:0] D0x = (E0x <<< 1) + (G0x <<< 2);
    // FALLBACK 1: E and G of the pixel in the divider's last stage, from
    // which the multiples are registered beside E.
    wire signed [XW-1:0] Epx, Gpx;
    wire signed [XW-1:0] Dpx = (Epx <<< 1) + (Gpx <<< 2);
    /* verilator lint_on UNUSEDSIGNAL */

    // x * k for a constant k: shifts and adds (a '*' would be mapped to a
    // DSP block by synth_ice40 -dsp).
    function signed [XW-1:0] mulk(input signed [XW-1:0] x, input integer k);
        integer b;
        begin
            mulk = {XW{1'b0}};
            for (b = 0; b < 30; b = b + 1)
                if (((k >> b) & 1) == 1) mulk = mulk + (x <<< b);
        end
    endfunction

    wire signed [XW-1:0] Ex  = {{(XW-EW){E[EW-1]}}, E};
    wire signed [XW-1:0] Gx  = {{(XW-EW){Gr[EW-1]}}, Gr};
    wire signed [XW-1:0] Wx  = {Wb[WW-1], Wb};
    wire signed [XW-1:0] Rx  = {R[WW-1], R};
    wire signed [XW-1:0] Dx  = {{(XW-EW-3){D[EW+2]}}, D};

    // ------------------------------------------------- the search, one clock
    wire up = Wb[WW-1];  // W <= 0: steps up, (4.14); else down, (4.15)

    // Pixel step taken this clock (FALLBACK 0; set below): every running
    // multiple of E steps with E. g[P+1] only steps m[P+1]; y[P] is read as
    // v[P] only; m0, g0 are wider than their registers.
    /* verilator lint_off UNUSEDSIGNAL */
    wire step;

    // m[j] = 2jE, g[j] = 4jG, j = 0..P+1; d[j] = jD = m[j] + g[j], j = 0..P.
    wire [(P+2)*XW-1:0] m_f, g_f, d_f;
    genvar j;
    generate
        for (j = 0; j <= P + 1; j = j + 1) begin : mult
            if (j == 0) begin : zero
                assign m_f[XW-1:0] = {XW{1'b0}};
                assign g_f[XW-1:0] = {XW{1'b0}};
                assign d_f[XW-1:0] = {XW{1'b0}};
            end else if ((j & (j - 1)) == 0) begin : shift
                assign m_f[j*XW +: XW] = Ex <<< ($clog2(j) + 1);
                assign g_f[j*XW +: XW] = Gx <<< ($clog2(j) + 2);
                assign d_f[j*XW +: XW] = Dx <<< $clog2(j);
            end else begin : reg_mult
                wire signed [XW-1:0] m0 = mulk(E0x, 2 * j), g0 = mulk(G0x, 4 * j), d0 = mulk(D0x, j);
                wire signed [XW-1:0] m1 = mulk(Epx, 2 * j), g1 = mulk(Gpx, 4 * j), d1 = mulk(Dpx, j);
                reg signed [MW-1:0] mr;
                reg signed [GW-1:0] gr;
                reg signed [DRW-1:0] dr;
                always @(posedge clk) begin
                    if (FALLBACK != 0) begin
                        mr <= m1[MW-1:0];
                        gr <= g1[GW-1:0];
                        dr <= d1[DRW-1:0];
                    end else if (ld) begin
                        mr <= m0[MW-1:0];
                        gr <= g0[GW-1:0];
                        dr <= d0[DRW-1:0];
                    end else if (step) begin
                        mr <= mr + gr[MW-1:0];
                        dr <= dr + {{(DRW-GW){gr[GW-1]}}, gr};
                    end
                end
                assign m_f[j*XW +: XW] = {{(XW-MW){mr[MW-1]}}, mr};
                assign g_f[j*XW +: XW] = {{(XW-GW){gr[GW-1]}}, gr};
                assign d_f[j*XW +: XW] = {{(XW-DRW){dr[DRW-1]}}, dr};
            end
        end
    endgenerate

    // Candidate j: y[j] = W - 1 + 2jE (up) or W - 1 - 2(j+1)E (down); a[j]:
    // the search ends within j steps (up: W + 2jE > 0, i.e. y[j] >= 0; down:
    // W - 2(j+1)E <= 0, i.e. y[j] < 0); v[j] its W - 1, r[j] its T - K, and
    // w[j] the next pixel's W - 1, (W - 1) + R +- jD: computed beside the
    // compare (a carry-save layer and one adder) so that the recurrence
    // W -> W passes one carry chain, not two.
    wire [(P+1)*XW-1:0] y_f, v_f, r_f, w_f;
    wire [(P+1)*NW-1:0] n_f;  // n +- j
    wire [P:0]          oor;  // |n +- j| >= 2^NLIM: the format's texel range is left (docs/METHODS.md)
    wire signed [NW-1:0] nlim = 1 <<< NLIM;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [P:0]          a;
    generate
        for (j = 0; j <= P; j = j + 1) begin : cand
            wire [XW-1:0]        op = up ? m_f[j*XW +: XW] : ~m_f[(j+1)*XW +: XW];
            wire signed [XW-1:0] y  = Wx + op + {{(XW-1){1'b0}}, !up};
            assign a[j] = up ^ y[XW-1];
            assign y_f[j*XW +: XW] = y;
            wire [XW-1:0] dop  = up ? d_f[j*XW +: XW] : ~d_f[j*XW +: XW];
            wire [XW-1:0] cs_s = Wx ^ Rx ^ dop;
            /* verilator lint_off UNUSEDSIGNAL */
            wire [XW-1:0] cs_c = (Wx & Rx) | (Wx & dop) | (Rx & dop);  // the sum is taken modulo 2^XW
            /* verilator lint_on UNUSEDSIGNAL */
            assign w_f[j*XW +: XW] = cs_s + {cs_c[XW-2:0], !up};
            // The index and its range test per candidate, beside the
            // compare rather than after the selection.
            localparam [NW-1:0] JN = j;
            wire signed [NW-1:0] nj = up ? n + JN : n - JN;
            assign n_f[j*NW +: NW] = nj;
            assign oor[j] = (nj >= nlim) || (nj <= -nlim);
            if (j == 0) begin : v0
                assign v_f[XW-1:0] = up ? y : Wx;
                assign r_f[XW-1:0] = Rx;
            end else begin : vj
                wire [XW-1:0] gop = up ? g_f[j*XW +: XW] : ~g_f[j*XW +: XW];
                assign v_f[j*XW +: XW] = up ? y : y_f[(j-1)*XW +: XW];
                assign r_f[j*XW +: XW] = Rx + gop + {{(XW-1){1'b0}}, !up};
            end
        end
    endgenerate

    // The first accepted j (a is monotone in j), one-hot.
    wire [P:0] sel = a & ~{a[P-1:0], 1'b0};
    wire       acc = a[P];
    reg  [XW-1:0] v_sel, r_sel, w_next;
    reg  [NW-1:0] n_sel;
    integer i;
    always @(*) begin
        v_sel = {XW{1'b0}};
        r_sel = {XW{1'b0}};
        w_next = {XW{1'b0}};
        n_sel = {NW{1'b0}};
        for (i = 0; i <= P; i = i + 1) begin
            v_sel = v_sel | ({XW{sel[i]}} & v_f[i*XW +: XW]);
            r_sel = r_sel | ({XW{sel[i]}} & r_f[i*XW +: XW]);
            w_next = w_next | ({XW{sel[i]}} & w_f[i*XW +: XW]);
            n_sel = n_sel | ({NW{sel[i]}} & n_f[i*NW +: NW]);
        end
    end
    wire                 n_oor = |(sel & oor);

    // More than CAP steps (W + 2·CAP·E <= 0, or W - 2(CAP+1)E > 0): the model
    // re-seeds.
    wire [XW-1:0]        fop = up ? mulk(Ex, 2 * CAP) : ~mulk(Ex, 2 * CAP + 2);
    wire signed [XW-1:0] yf  = Wx + fop + {{(XW-1){1'b0}}, !up};
    wire                 far = !(up ^ yf[XW-1]);

    generate
        if (FALLBACK == 0) begin : stall
            localparam S_IDLE = 2'd0, S_RUN = 2'd1, S_DIV = 2'd2, S_FIN = 2'd3;
            reg [1:0] state;
            reg signed [N2W-1:0] N2;
            /* verilator lint_off UNUSEDSIGNAL */
            reg signed [N2W-1:0] Ar;  // 2A is used: |A| < 2^(N2W-2)
            /* verilator lint_on UNUSEDSIGNAL */
            reg signed [KW-1:0]  Kr;
            reg        [LW-1:0]  left;
            reg                  o2r, rs;
            wire signed [EW-1:0] twoG = {Gr[EW-2:0], 1'b0};
            wire signed [N2W-1:0] twoA = {Ar[N2W-2:0], 1'b0};

            // Re-seed divider state: rem / dsh restoring division; S starts at
            // 2G*2o - K and accumulates +-4G*q, so that it ends at T - K with
            // T = 2G*(2n + 2o) and no multiplier.
            reg        [DW-1:0]  rem, dsh;
            reg signed [WW-1:0]  gsh, S;
            reg        [NLIM-1:0] q;
            reg        [4:0]     cnt;
            reg                  neg;

            // n = floor_div(a, b), a = 2*N2 + (1 - 2o)*E, b = 2E > 0. For a < 0,
            // floor(a/b) = -floor((-a + b - 1)/b): divide a' >= 0, negate after.
            wire signed [DW:0]   a_s  = {N2[N2W-1], N2, 1'b0} + (o2r ? {(DW+1){1'b0}} : {{(DW-EW+1){E[EW-1]}}, E});
            wire        [DW:0]   b_u  = {{(DW-EW){1'b0}}, E, 1'b0};
            wire        [DW:0]   a_p  = a_s[DW] ? (-a_s + b_u - 1'b1) : a_s;
            // floor(a'/b) >= 2^NLIM: the re-seeded index leaves the format.
            wire                 d_ovf = a_p >= (b_u << NLIM);
            wire                 d_ge  = rem >= dsh;
            wire signed [WW-1:0] g4top = {Gx[WW-NLIM-2:0], 2'b00, {(NLIM-1){1'b0}}};  // 4G << (NLIM-1)
            wire signed [WW-1:0] Kw    = {{(WW-KW){Kr[KW-1]}}, Kr};
            wire signed [WW-1:0] s0    = (o2r ? {{(WW-EW){twoG[EW-1]}}, twoG} : {WW{1'b0}}) - Kw;

            wire run  = state == S_RUN;
            wire last = acc && (n_oor || left == 1);
            assign step  = !rst && run && !far && acc && !last;
            assign ready = (state == S_IDLE) || (run && (far ? d_ovf : last));
            assign Epx = {XW{1'b0}};
            assign Gpx = {XW{1'b0}};

            always @(posedge clk) begin
                out_valid <= 1'b0;
                if (rst) begin
                    state <= S_IDLE;
                end else begin
                    if (run) begin
                        if (far) begin
                            if (d_ovf) begin
                                out_valid  <= 1'b1;
                                out_oor    <= 1'b1;
                                out_reseed <= 1'b1;
                                state      <= S_IDLE;
                            end else begin
                                rem   <= a_p[DW-1:0];
                                dsh   <= b_u[DW-1:0] << (NLIM - 1);
                                gsh   <= a_s[DW] ? -g4top : g4top;
                                S     <= s0;
                                q     <= 0;
                                neg   <= a_s[DW];
                                cnt   <= NLIM - 1;
                                state <= S_DIV;
                            end
                        end else if (acc) begin
                            out_valid  <= 1'b1;
                            out_oor    <= n_oor;
                            out_reseed <= rs;
                            out_n      <= n_sel;
                            out_W      <= v_sel[WW-1:0] + 1'b1;
                            if (last) begin
                                state <= S_IDLE;
                            end else begin
                                // Pixel step x -> x + 1 (docs/METHODS.md, "Formula").
                                E    <= E + twoG;
                                Wb   <= w_next[WW-1:0];
                                D    <= D + {Gr[EW-1], Gr, 2'b00};
                                R    <= r_sel[WW-1:0];
                                n    <= n_sel;
                                N2   <= N2 + twoA;
                                left <= left - 1'b1;
                                rs   <= 1'b0;
                            end
                        end else begin
                            // STEPS lattice steps, no acceptance yet.
                            Wb <= v_f[P*XW +: WW];
                            R <= r_f[P*XW +: WW];
                            n <= n_f[P*NW +: NW];
                        end
                    end else if (state == S_DIV) begin
                        if (d_ge) begin
                            rem <= rem - dsh;
                            q   <= q | ({{(NLIM-1){1'b0}}, 1'b1} << cnt);
                            S   <= S + gsh;
                        end
                        dsh <= dsh >> 1;
                        gsh <= gsh >>> 1;
                        cnt <= cnt - 1'b1;
                        if (cnt == 0) state <= S_FIN;
                    end else if (state == S_FIN) begin
                        // n = +-q; W = 2E - r with r the floor remainder
                        // (docs/HARDWARE.md), so W - 1 = r' or 2E + ~r; T - K
                        // accumulated in S.
                        n  <= neg ? -$signed({{(NW-NLIM){1'b0}}, q}) : $signed({{(NW-NLIM){1'b0}}, q});
                        Wb <= neg ? $signed({{(WW-DW){1'b0}}, rem})
                                  : {Ex[WW-2:0], 1'b0} + ~$signed({{(WW-DW){1'b0}}, rem});
                        R  <= S;
                        rs <= 1'b1;
                        state <= S_RUN;
                    end
                    if (load) begin
                        E <= E0; Gr <= G; N2 <= N2_0; Ar <= A; Wb <= W0 - 1'b1; Kr <= K; n <= n0;
                        D <= D0x[EW+2:0];
                        R <= {{(WW-TW){T0[TW-1]}}, T0} - {{(WW-KW){K[KW-1]}}, K};
                        o2r <= o2; left <= len; rs <= 1'b0;
                        state <= (len == 0) ? S_IDLE : S_RUN;
                    end
                end
            end
        end else begin : ahead
            // ------------------------------------------ the span's pixels, in order
            // One pixel a clock leaves this stage while `left` > 0: its E, N2
            // (stepped by 2G, 2A: docs/METHODS.md, "Formula"), and the
            // triangle's G, K and 2o. A load replaces what is left of a span.
            reg signed [EW-1:0]  fE, fG;
            reg signed [N2W-1:0] fN2;
            /* verilator lint_off UNUSEDSIGNAL */
            reg signed [N2W-1:0] fA;  // 2A is used: |A| < 2^(N2W-2)
            /* verilator lint_on UNUSEDSIGNAL */
            reg signed [KW-1:0]  fK;
            reg        [LW-1:0]  fleft;
            reg                  fo2, ffirst;
            wire                 fv = fleft != 0;
            always @(posedge clk) begin
                if (rst) begin
                    fleft <= 0;
                end else begin
                    if (fv) begin
                        fE     <= fE + {fG[EW-2:0], 1'b0};
                        fN2    <= fN2 + {fA[N2W-2:0], 1'b0};
                        fleft  <= fleft - 1'b1;
                        ffirst <= 1'b0;
                    end
                    if (load) begin
                        fE <= E0; fG <= G; fN2 <= N2_0; fA <= A; fK <= K; fo2 <= o2;
                        fleft <= len; ffirst <= 1'b1;
                    end
                end
            end
            // Idle, or the span's last pixel leaves the stage now.
            assign ready = fleft <= 1;
            assign step  = 1'b0;

            // ------------------- the divider: NLIM + 1 stages, a quotient bit each
            // n = floor_div(a, b), a = 2*N2 + (1 - 2o)*E, b = 2E > 0. For a < 0,
            // floor(a/b) = -floor((-a + b - 1)/b): divide a' >= 0, negate after.
            // Stage 0 forms a' and the range test; stage k (1..NLIM) decides
            // quotient bit NLIM - k by one compare-subtract of b << (NLIM - k),
            // a' < b << (NLIM - k + 1) on entry. Beside it S, from 2G*2o - K,
            // adds +-4G << (NLIM - k) with each quotient bit, so that it ends
            // at T - K = 2G*(2n + 2o) - K with no multiplier.
            wire signed [DW:0]   a_s  = {fN2[N2W-1], fN2, 1'b0} + (fo2 ? {(DW+1){1'b0}} : {{(DW-EW+1){fE[EW-1]}}, fE});
            wire        [DW:0]   b_u  = {{(DW-EW){1'b0}}, fE, 1'b0};
            wire        [DW:0]   a_p  = a_s[DW] ? (-a_s + b_u - 1'b1) : a_s;
            wire signed [WW-1:0] s0   = (fo2 ? {{(WW-EW-1){fG[EW-1]}}, fG, 1'b0} : {WW{1'b0}})
                                        - {{(WW-KW){fK[KW-1]}}, fK};
            localparam RW = EW + NLIM;  // a' below b << NLIM: E < 2^(EW-1)
            // Stage k's outputs: the remainder (RW bits, zero above its
            // EW + NLIM - k), S, E, G, the quotient so far, and the flags.
            // (The remainders' bits above their bound and the quotient's
            // top bit, shifted out, are not read.)
            /* verilator lint_off UNUSEDSIGNAL */
            wire [(NLIM+1)*RW-1:0]   rem_f;
            wire [(NLIM+1)*NLIM-1:0] q_f;
            /* verilator lint_on UNUSEDSIGNAL */
            wire [(NLIM+1)*WW-1:0]   S_f;
            wire [(NLIM+1)*EW-1:0]   E_f, G_f;
            wire [NLIM:0]            v_f_, first_f, neg_f, ovf_f;
            genvar k;
            for (k = 0; k <= NLIM; k = k + 1) begin : div
                localparam integer I = NLIM - k;  // the quotient bit decided here (k >= 1)
                reg        [EW+I-1:0] rem;
                reg signed [WW-1:0]   S;
                reg signed [EW-1:0]   Ek, Gk;
                reg        [NLIM-1:0] q;
                reg                   v, first, neg, ovf;
                if (k == 0) begin : init
                    always @(posedge clk) begin
                        v     <= fv && !rst;
                        first <= ffirst;
                        rem   <= a_p[RW-1:0];
                        S     <= s0;
                        Ek    <= fE;
                        Gk    <= fG;
                        q     <= {NLIM{1'b0}};
                        neg   <= a_s[DW];
                        // floor(a'/b) >= 2^NLIM: the index leaves the format.
                        ovf   <= a_p >= (b_u << NLIM);
                    end
                    assign rem_f[k*RW +: RW] = rem;
                end else begin : step_bit
                    wire [EW+I:0]   rin = rem_f[(k-1)*RW +: EW+I+1];
                    wire signed [EW-1:0] Ei = E_f[(k-1)*EW +: EW];
                    wire signed [EW-1:0] Gi = G_f[(k-1)*EW +: EW];
                    wire signed [WW-1:0] Si = S_f[(k-1)*WW +: WW];
                    wire [EW+I-1:0] bsh = {{(I+1){1'b0}}, Ei[EW-2:0]} << (I + 1);  // b << I
                    wire [EW+I+1:0] df  = {1'b0, rin} - {2'b00, bsh};
                    wire            ge  = !df[EW+I+1];
                    wire signed [WW-1:0] g4 = $signed({{(WW-EW){Gi[EW-1]}}, Gi}) <<< (I + 2);
                    always @(posedge clk) begin
                        v     <= v_f_[k-1] && !rst;
                        first <= first_f[k-1];
                        rem   <= ge ? df[EW+I-1:0] : rin[EW+I-1:0];
                        S     <= !ge ? Si : neg_f[k-1] ? Si - g4 : Si + g4;
                        Ek    <= Ei;
                        Gk    <= Gi;
                        q     <= {q_f[(k-1)*NLIM +: NLIM-1], ge};
                        neg   <= neg_f[k-1];
                        ovf   <= ovf_f[k-1];
                    end
                    assign rem_f[k*RW +: RW] = {{(RW-EW-I){1'b0}}, rem};
                end
                assign S_f[k*WW +: WW]       = S;
                assign E_f[k*EW +: EW]       = Ek;
                assign G_f[k*EW +: EW]       = Gk;
                assign q_f[k*NLIM +: NLIM]   = q;
                assign v_f_[k]   = v;
                assign first_f[k] = first;
                assign neg_f[k]  = neg;
                assign ovf_f[k]  = ovf;
            end

            // ---------------- the divider's answer beside the search's registers
            // n = +-q; W = 2E - r with r the floor remainder, so W - 1 = r' or
            // 2E + ~r (docs/HARDWARE.md); the next pixel's W - 1 is W - 1 + T - K.
            wire signed [EW-1:0] El = E_f[NLIM*EW +: EW];
            wire signed [EW-1:0] Gl = G_f[NLIM*EW +: EW];
            wire        [NLIM-1:0] ql = q_f[NLIM*NLIM +: NLIM];
            wire        [WW-1:0] rl = {{(WW-EW){1'b0}}, rem_f[NLIM*RW +: EW]};
            wire signed [WW-1:0] Sl = S_f[NLIM*WW +: WW];
            wire signed [WW-1:0] wl = neg_f[NLIM] ? $signed(rl) : {{(WW-EW-1){1'b0}}, El, 1'b0} + ~$signed(rl);
            wire signed [NW-1:0] nq = $signed({{(NW-NLIM){1'b0}}, ql});
            assign Epx = {{(XW-EW){El[EW-1]}}, El};
            assign Gpx = {{(XW-EW){Gl[EW-1]}}, Gl};
            reg                  pv, pfirst, povf;
            reg signed [NW-1:0]  pn;
            reg signed [WW-1:0]  pWb, pwn, pS;
            always @(posedge clk) begin
                pv     <= v_f_[NLIM] && !rst;
                pfirst <= first_f[NLIM];
                povf   <= ovf_f[NLIM];
                pn     <= neg_f[NLIM] ? -nq : nq;
                pWb    <= wl;
                pwn    <= wl + Sl;
                pS     <= Sl;
                E      <= El;
                Gr     <= Gl;
                D      <= Dpx[EW+2:0];
            end

            // ------------------------------------------- one pixel every clock
            // The search answers where it ends within STEPS steps; the span's
            // first pixel, a re-seed (far) and a longer search take the
            // divider's answer, which is the same n and W (the unique
            // 0 < W <= 2E). A pixel flagged out_oor ends its span: the span's
            // later pixels, already in the pipeline, are dropped.
            //
            // FALLBACK 2 takes the divider's answer for every pixel: the
            // search is then not needed, and the re-seed flag (more than CAP
            // steps) is |n - n_prev| > CAP, the index's move from the
            // previous pixel.
            reg  dead;
            /* verilator lint_off UNUSEDSIGNAL */
            wire signed [NW:0] dn = {pn[NW-1], pn} - {n[NW-1], n};
            localparam signed [NW:0] CAPN = CAP;
            wire div_far = (dn > CAPN) || (dn < -CAPN);
            /* verilator lint_on UNUSEDSIGNAL */
            wire use_div = FALLBACK == 2 || pfirst || far || !acc;
            wire oor_now = use_div ? povf : n_oor;
            always @(posedge clk) begin
                out_valid <= 1'b0;
                if (rst) begin
                    dead <= 1'b0;
                end else if (pv && (pfirst || !dead)) begin
                    out_valid  <= 1'b1;
                    out_oor    <= oor_now;
                    out_reseed <= !pfirst && (FALLBACK == 2 ? div_far : far);
                    out_n      <= use_div ? pn : n_sel;
                    out_W      <= (use_div ? pWb : v_sel[WW-1:0]) + 1'b1;
                    Wb         <= use_div ? pwn : w_next[WW-1:0];
                    R          <= use_div ? pS : r_sel[WW-1:0];
                    n          <= use_div ? pn : n_sel;
                    dead       <= oor_now;
                end
            end
        end
    endgenerate
endmodule
