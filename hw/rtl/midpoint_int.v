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
// One lattice step or one accepted pixel per clock: a pixel whose search
// takes s steps costs 1 + s cycles; a re-seed costs CAP + 1 + NLIM + 2 more
// (docs/HARDWARE.md gives the measured cycles per pixel).
//
// Interface: `load` (accepted whenever asserted; it aborts a span in
// progress) latches the span's start values and len, the number of pixels
// to deliver; `ready` says that a load in this cycle loses nothing (idle, or
// this cycle accepts the span's last pixel). out_valid for one cycle per
// delivered pixel, registered; out_oor marks the pixel at which the integer
// path ends (out_n, out_W are then not meaningful) and the span stops there.
module midpoint_int #(
    parameter EW   = 43,  // E = G*X2 + H*Y2 + 2I > 0
    parameter N2W  = 59,  // N2 = A*X2 + B*Y2 + 2C, and A
    parameter WW   = 62,  // W
    parameter TW   = 60,  // T = 2G*M
    parameter KW   = 61,  // K = 4A - 2G
    parameter NW   = 18,  // lattice index n (|n| < 2^NLIM plus CAP steps)
    parameter NLIM = 16,  // the format's texel range: |n| < 2^NLIM
    parameter CAP  = 32,  // lattice steps before a re-seed
    parameter LW   = 7    // span length counter (spans are at most 64 pixels)
) (
    input  wire                  clk,
    input  wire                  rst,
    input  wire                  load,
    input  wire                  o2,     // 2o: 1 texel centres, 0 texel edges
    input  wire signed [EW-1:0]  G,
    input  wire signed [N2W-1:0] A,
    input  wire signed [EW-1:0]  E0,
    input  wire signed [N2W-1:0] N2_0,
    input  wire signed [NW-1:0]  n0,
    input  wire signed [WW-1:0]  W0,
    input  wire signed [TW-1:0]  T0,
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
    localparam CW = 6;  // step counter, 0..CAP

    localparam S_IDLE = 2'd0, S_RUN = 2'd1, S_DIV = 2'd2, S_FIN = 2'd3;
    reg [1:0] state;

    reg signed [EW-1:0]  E, Gr;
    reg signed [N2W-1:0] N2;
    /* verilator lint_off UNUSEDSIGNAL */
    reg signed [N2W-1:0] Ar;  // 2A is used: |A| < 2^(N2W-2)
    /* verilator lint_on UNUSEDSIGNAL */
    reg signed [WW-1:0]  W;
    reg signed [TW-1:0]  T;
    reg signed [KW-1:0]  Kr;
    reg signed [NW-1:0]  n;
    reg        [LW-1:0]  left;
    reg        [CW-1:0]  it;
    reg                  o2r, rs;

    // Re-seed divider state: rem / dsh restoring division, S accumulates
    // 4G*q so that T = 2G*(2q + 2o) needs no multiplier.
    reg        [DW-1:0]  rem, dsh;
    reg signed [TW-1:0]  gsh, S;
    reg        [NLIM-1:0] q;
    reg        [4:0]     cnt;
    reg                  neg;

    // ---------------------------------------------------------- search step
    wire signed [WW-1:0] twoE  = {{(WW-EW-1){E[EW-1]}}, E, 1'b0};
    wire                 w_pos = W > 0;
    wire                 w_le  = W <= twoE;
    wire                 acc   = w_pos && w_le;
    wire                 capped = it == CAP[CW-1:0];
    // |n| >= 2^NLIM: the format's texel range is left (docs/METHODS.md).
    wire signed [NW-1:0] nlim  = 1 <<< NLIM;
    wire                 n_oor = (n >= nlim) || (n <= -nlim);
    wire signed [TW-1:0] fourG = {{(TW-EW-2){Gr[EW-1]}}, Gr, 2'b00};
    wire signed [EW-1:0] twoG  = {Gr[EW-2:0], 1'b0};
    wire signed [WW-1:0] Tw    = {{(WW-TW){T[TW-1]}}, T};
    wire signed [WW-1:0] Kw    = {{(WW-KW){Kr[KW-1]}}, Kr};
    wire signed [N2W-1:0] twoA = {Ar[N2W-2:0], 1'b0};

    // ------------------------------------------- re-seed: exact floor division
    // n = floor_div(a, b), a = 2*N2 + (1 - 2o)*E, b = 2E > 0. For a < 0,
    // floor(a/b) = -floor((-a + b - 1)/b): divide a' >= 0, negate after.
    wire signed [DW:0]   a_s  = {N2[N2W-1], N2, 1'b0} + (o2r ? {(DW+1){1'b0}} : {{(DW-EW+1){E[EW-1]}}, E});
    wire        [DW:0]   b_u  = {{(DW-EW){1'b0}}, E, 1'b0};
    wire        [DW:0]   a_p  = a_s[DW] ? (-a_s + b_u - 1'b1) : a_s;
    // floor(a'/b) >= 2^NLIM: the re-seeded index leaves the format.
    wire                 d_ovf = a_p >= (b_u << NLIM);
    wire                 d_ge  = rem >= dsh;

    assign ready = (state == S_IDLE) ||
                   (state == S_RUN && ((acc && (n_oor || left == 1)) || (!acc && capped && d_ovf)));

    always @(posedge clk) begin
        out_valid <= 1'b0;
        if (rst) begin
            state <= S_IDLE;
        end else begin
            if (state == S_RUN) begin
                if (acc) begin
                    out_valid  <= 1'b1;
                    out_oor    <= n_oor;
                    out_reseed <= rs;
                    out_n      <= n;
                    out_W      <= W;
                    if (n_oor || left == 1) begin
                        state <= S_IDLE;
                    end else begin
                        // Pixel step x -> x + 1 (docs/METHODS.md, "Formula").
                        E    <= E + twoG;
                        W    <= W + Tw - Kw;
                        N2   <= N2 + twoA;
                        left <= left - 1'b1;
                        it   <= 0;
                        rs   <= 1'b0;
                    end
                end else if (capped) begin
                    if (d_ovf) begin
                        out_valid <= 1'b1;
                        out_oor   <= 1'b1;
                        out_reseed <= 1'b1;
                        state     <= S_IDLE;
                    end else begin
                        rem   <= a_p[DW-1:0];
                        dsh   <= b_u[DW-1:0] << (NLIM - 1);
                        gsh   <= fourG <<< (NLIM - 1);
                        S     <= 0;
                        q     <= 0;
                        neg   <= a_s[DW];
                        cnt   <= NLIM - 1;
                        state <= S_DIV;
                    end
                end else if (!w_pos) begin
                    // Lattice step up, (4.14).
                    n  <= n + 1'b1;
                    W  <= W + twoE;
                    T  <= T + fourG;
                    it <= it + 1'b1;
                end else begin
                    // Lattice step down, (4.15).
                    n  <= n - 1'b1;
                    W  <= W - twoE;
                    T  <= T - fourG;
                    it <= it + 1'b1;
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
                // (docs/HARDWARE.md); T = 2G*(2n + 2o) = 4G*n + 2G*2o.
                n  <= neg ? -$signed({{(NW-NLIM){1'b0}}, q}) : $signed({{(NW-NLIM){1'b0}}, q});
                W  <= neg ? $signed({{(WW-DW){1'b0}}, rem}) + 1'b1
                          : twoE - $signed({{(WW-DW){1'b0}}, rem});
                T  <= (neg ? -S : S) + (o2r ? {{(TW-EW){twoG[EW-1]}}, twoG} : {TW{1'b0}});
                it <= 0;
                rs <= 1'b1;
                state <= S_RUN;
            end
            if (load) begin
                E <= E0; Gr <= G; N2 <= N2_0; Ar <= A; W <= W0; T <= T0; Kr <= K; n <= n0;
                o2r <= o2; left <= len; it <= 0; rs <= 1'b0;
                state <= (len == 0) ? S_IDLE : S_RUN;
            end
        end
    end
endmodule
