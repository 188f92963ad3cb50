// exact — the baseline per-pixel interpolator: E = 2/w·2^s and
// N2 = 2·P·(u/w)·2^s (u and v) stepped linearly along a span, exactly, as
// integers; per pixel one reciprocal of E (a 256-entry seed table in block
// RAM and one Newton–Raphson step, r1 = r0·(2 - m·r0)) and two multiplies,
// t = N2/E in texels with FRAC fraction bits. Bit-exact with the C model
// persp__hw_exact_pixel (src/analysis/hw_models.c; the format is in
// docs/HARDWARE.md, "exact"). Every multiply is 16 x 16 or 32 x 16 bits so
// that it maps onto the iCE40's SB_MAC16 (one and two each).
//
// The stages after the stepping are hw/rtl/exact_stages.v (shared with
// subdiv.v). One pixel per clock; a pixel's output comes LAT = 7 clocks after its
// stepping stage. Interface: `load` latches a span (E0, N2u0, N2v0, the
// steps 2G, 2Au, 2Av and len pixels) whenever asserted; `ready` says that a
// load in this cycle loses nothing. out_ovf: the pixel's |t| reaches 2^15
// texels, outside the format (out_tu, out_tv are then not meaningful).
module exact #(
    parameter EW  = 41,  // E (signed register; 0 < E < 2^40 on a span)
    parameter NW  = 56,  // N2 (signed)
    parameter SW  = 32,  // normalised numerator Ns
    parameter TOW = 25,  // outputs t*2^8
    parameter LW  = 7
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
    input  wire        [LW-1:0] len,
    output wire                 ready,
    output reg                  out_valid,
    output reg                  out_ovf,
    output reg  signed [TOW-1:0] out_tu,
    output reg  signed [TOW-1:0] out_tv
);
    // ------------------------------------------------ S0: span stepping
    reg signed [EW-1:0] E, G2r;
    reg signed [NW-1:0] Nu, Nv, Au2r, Av2r;
    reg        [LW-1:0] left;
    wire v0 = left != 0;
    assign ready = left <= 1;

    // ------------------------------------------------ S1..S6
    wire                  v6, ovf6;
    wire signed [TOW-1:0] tu6, tv6;
    exact_stages #(.EW(EW), .NW(NW), .SW(SW), .TOW(TOW)) stages (
        .clk(clk), .rst(rst), .in_valid(v0), .E(E), .Nu(Nu), .Nv(Nv),
        .out_valid(v6), .out_ovf(ovf6), .out_tu(tu6), .out_tv(tv6));

    always @(posedge clk) begin
        if (rst) begin
            left <= 0;
            out_valid <= 0;
        end else begin
            // S0
            if (load) begin
                E <= E0; Nu <= Nu0; Nv <= Nv0; G2r <= G2; Au2r <= Au2; Av2r <= Av2; left <= len;
            end else if (v0) begin
                E <= E + G2r; Nu <= Nu + Au2r; Nv <= Nv + Av2r; left <= left - 1'b1;
            end
            // S7
            out_valid <= v6; out_ovf <= ovf6; out_tu <= tu6; out_tv <= tv6;
        end
    end
endmodule
