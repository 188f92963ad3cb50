// exact_stages — exact's per-pixel datapath after the span stepping: from
// E and the numerators N2u, N2v of a pixel to t_u, t_v (exact.v's stages
// S1..S6, the format in docs/HARDWARE.md, "exact"). One pixel per clock:
// what enters with `in_valid` leaves six clocks later as the combinational
// out_* of S6 (`out_valid`), which the instantiating module registers: the
// output stage of exact (hw/rtl/exact.v), and the node queue of subdiv
// (hw/rtl/subdiv.v), so that both share these stages, bit for bit.
module exact_stages #(
    parameter EW  = 41,  // E (signed register; 0 < E < 2^40 on a span)
    parameter NW  = 56,  // N2 (signed)
    parameter SW  = 32,  // normalised numerator Ns
    parameter TOW = 25   // outputs t*2^8
) (
    input  wire                  clk,
    input  wire                  rst,
    input  wire                  in_valid,
    input  wire signed [EW-1:0]  E,
    input  wire signed [NW-1:0]  Nu,
    input  wire signed [NW-1:0]  Nv,
    output wire                  out_valid,
    output wire                  out_ovf,
    output wire signed [TOW-1:0] out_tu,
    output wire signed [TOW-1:0] out_tv
);
    localparam MB = EW - 1;        // mantissa bits of m = E << lz
    localparam SH = NW - SW;       // Ns = (N2 << lz) >>> SH

    // --------------------------------------------------- seed table (BRAM)
    reg [15:0] rom [0:255];
    /* verilator lint_off UNUSEDSIGNAL */
    integer i, seed;
    /* verilator lint_on UNUSEDSIGNAL */
    initial
        for (i = 0; i < 256; i = i + 1) begin
            seed = 33554432 / (513 + 2 * i);  // 2^24 / (256.5 + i): 1/m mid-interval
            rom[i] = seed[15:0];
        end

    // ------------------------------------------------ S1: normalise E
    reg [5:0] lz_c;
    integer k;
    always @* begin
        lz_c = 6'd0;
        for (k = 0; k < MB; k = k + 1)
            if (E[k]) lz_c = MB[5:0] - 6'd1 - k[5:0];
    end
    /* verilator lint_off UNUSEDSIGNAL */
    reg        [MB-1:0] m1;  // the seed and m16 read its top 16 bits
    /* verilator lint_on UNUSEDSIGNAL */
    reg        [5:0]    lz1;
    reg signed [NW-1:0] Nu1, Nv1;
    reg                 v1;

    // ------------------------------------ S2: seed, numerators normalised
    wire signed [NW+MB-1:0] shu = $signed({{MB{Nu1[NW-1]}}, Nu1}) <<< lz1;
    wire signed [NW+MB-1:0] shv = $signed({{MB{Nv1[NW-1]}}, Nv1}) <<< lz1;
    // N2 << lz must fit NW bits: |t| < 2^15 texels.
    wire ovf_u = shu[NW+MB-1:NW-1] != {(MB+1){shu[NW-1]}};
    wire ovf_v = shv[NW+MB-1:NW-1] != {(MB+1){shv[NW-1]}};
    reg        [15:0]   r0_2, m16_2;
    reg signed [SW-1:0] Nsu2, Nsv2;
    reg                 ovf2, v2;

    // ------------------------------- S3..S5: r1 = r0 - r0*(m16*r0/2^31 - 1)
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
    wire signed [31:0]  cs = c4 >>> 22;  // |cs| < 2^10
    wire signed [17:0]  r1w = $signed({2'b00, r0_4}) - cs[17:0];
    // 1/m in (1/2, 1]: r1 clamped to [2^15, 2^16) as in the C model.
    wire        [15:0]  r1 = r1w > 18'sd65535 ? 16'd65535 : (r1w < 18'sd32768 ? 16'd32768 : r1w[15:0]);
    /* verilator lint_on UNUSEDSIGNAL */
    reg         [14:0]  rr5;  // r1 - 2^15

    // ------------------------------------- S6, S7: t = Ns*r1 >>> 23
    reg signed [SW+16:0] pu6, pv6;
    /* verilator lint_off UNUSEDSIGNAL */
    wire signed [SW+16:0] su = $signed({{2{Nsu6[SW-1]}}, Nsu6, 15'd0}) + pu6;
    wire signed [SW+16:0] sv = $signed({{2{Nsv6[SW-1]}}, Nsv6, 15'd0}) + pv6;
    /* verilator lint_on UNUSEDSIGNAL */

    assign out_valid = v6;
    assign out_ovf = ovf6;
    assign out_tu = su[TOW+22:23];
    assign out_tv = sv[TOW+22:23];

    always @(posedge clk) begin
        if (rst) begin
            v1 <= 0; v2 <= 0; v3 <= 0; v4 <= 0; v5 <= 0; v6 <= 0;
        end else begin
            // S1
            v1 <= in_valid; lz1 <= lz_c; m1 <= E[MB-1:0] << lz_c; Nu1 <= Nu; Nv1 <= Nv;
            // S2
            v2 <= v1; r0_2 <= rom[m1[MB-2:MB-9]]; m16_2 <= m1[MB-1:MB-16];
            Nsu2 <= shu[SW+SH-1:SH]; Nsv2 <= shv[SW+SH-1:SH]; ovf2 <= ovf_u || ovf_v;
            // S3
            v3 <= v2; p3 <= m16_2 * r0_2; r0_3 <= r0_2; Nsu3 <= Nsu2; Nsv3 <= Nsv2; ovf3 <= ovf2;
            // S4
            v4 <= v3; c4 <= $signed({1'b0, r0_3[15:1]}) * $signed(d8w[15:0]); r0_4 <= r0_3;
            Nsu4 <= Nsu3; Nsv4 <= Nsv3; ovf4 <= ovf3;
            // S5
            v5 <= v4; rr5 <= r1[14:0]; Nsu5 <= Nsu4; Nsv5 <= Nsv4; ovf5 <= ovf4;
            // S6
            v6 <= v5; pu6 <= Nsu5 * $signed({1'b0, rr5}); pv6 <= Nsv5 * $signed({1'b0, rr5});
            Nsu6 <= Nsu5; Nsv6 <= Nsv5; ovf6 <= ovf5;
        end
    end
endmodule
