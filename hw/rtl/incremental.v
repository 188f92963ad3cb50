// incremental — [Romaniuk-Incr]'s incremental form, (4): the numerators
// and the denominator of Heckbert's form advanced by one addition each per
// pixel, one reciprocal and two multiplies per pixel, in the two
// counter-directional streams of [Romaniuk-Incr] Fig. 4 (incremental:bidir):
// one chain from the span's left end (+2G, +2A), one from its right end
// (-2G, -2A), meeting in the middle, so two pixels per clock.
//
// In integers the running sums are the exact values start + k·step, so a
// single chain would be hw/rtl/exact.v itself; each chain here is an
// instance of exact (Verilator finds it by -y hw/rtl; scripts/hw.sh gives
// Yosys both files), and both are bit-exact with persp__hw_incremental_span
// (src/analysis/hw_models_span.c). The left chain delivers pixels
// 0 .. ceil(n/2) - 1, the right chain n - 1 down to ceil(n/2), in the same
// cycles; ready is the left chain's (it never has fewer pixels). Inputs as
// exact's plus the span's end values (E1, Nu1, Nv1 = the start values +
// (len - 1) steps, from set-up).
module incremental #(
    parameter EW  = 41,
    parameter NW  = 56,
    parameter TOW = 25,
    parameter LW  = 7
) (
    input  wire                  clk,
    input  wire                  rst,
    input  wire                  load,
    input  wire signed [EW-1:0]  E0,
    input  wire signed [EW-1:0]  G2,
    input  wire signed [NW-1:0]  Nu0,
    input  wire signed [NW-1:0]  Nv0,
    input  wire signed [NW-1:0]  Au2,
    input  wire signed [NW-1:0]  Av2,
    input  wire signed [EW-1:0]  E1,
    input  wire signed [NW-1:0]  Nu1,
    input  wire signed [NW-1:0]  Nv1,
    input  wire        [LW-1:0]  len,
    output wire                  ready,
    output wire                  out_valid_l,
    output wire                  out_ovf_l,
    output wire signed [TOW-1:0] out_tu_l,
    output wire signed [TOW-1:0] out_tv_l,
    output wire                  out_valid_r,
    output wire                  out_ovf_r,
    output wire signed [TOW-1:0] out_tu_r,
    output wire signed [TOW-1:0] out_tv_r
);
    /* verilator lint_off UNUSEDSIGNAL */
    wire ready_r;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [LW-1:0] half_l = (len + 1'b1) >> 1;
    wire [LW-1:0] half_r = len >> 1;
    exact #(.EW(EW), .NW(NW), .TOW(TOW), .LW(LW)) chain_l (
        .clk(clk), .rst(rst), .load(load), .E0(E0), .G2(G2), .Nu0(Nu0), .Nv0(Nv0), .Au2(Au2), .Av2(Av2),
        .len(half_l), .ready(ready), .out_valid(out_valid_l), .out_ovf(out_ovf_l), .out_tu(out_tu_l),
        .out_tv(out_tv_l));
    exact #(.EW(EW), .NW(NW), .TOW(TOW), .LW(LW)) chain_r (
        .clk(clk), .rst(rst), .load(load), .E0(E1), .G2(-G2), .Nu0(Nu1), .Nv0(Nv1), .Au2(-Au2), .Av2(-Av2),
        .len(half_r), .ready(ready_r), .out_valid(out_valid_r), .out_ovf(out_ovf_r), .out_tu(out_tu_r),
        .out_tv(out_tv_r));
endmodule
