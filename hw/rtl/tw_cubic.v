// tw_cubic — t_w along a span by the cubic approximation of [Romanyuk-PCF]
// §4.3 (nodes 0, L/3, 2L/3, L), by forward differences: per pixel three
// additions, no division. d0..d3 (DF fraction bits) are the span's set-up's
// (four divisions per span, outside); bit-exact with persp__hw_tw_run
// (src/analysis/hw_models_shade.c; docs/HARDWARE.md, "t_w"). Output
// t_w * 2^TF, floor, clamped to [0, 1]. One pixel per clock, latency 1.
module tw_cubic #(
    parameter DW = 40,
    parameter DF = 32,
    parameter TF = 16,
    parameter LW = 7
) (
    input  wire                 clk,
    input  wire                 rst,
    input  wire                 load,
    input  wire        [LW-1:0] len,
    input  wire signed [DW-1:0] d0_in,
    input  wire signed [DW-1:0] d1_in,
    input  wire signed [DW-1:0] d2_in,
    input  wire signed [DW-1:0] d3_in,
    output wire                 ready,
    output reg                  out_valid,
    output reg         [TF:0]   out_t
);
    reg signed [DW-1:0] d0, d1, d2, d3;
    reg [LW-1:0] left;
    wire busy = left != 0;
    assign ready = left <= 1;
    localparam QW = DW - (DF - TF);
    wire signed [QW-1:0] tq = d0[DW-1:DF-TF];
    wire [TF:0] tc = tq[QW-1] ? {(TF+1){1'b0}} :
                     (tq > $signed({{(QW-TF-1){1'b0}}, 1'b1, {TF{1'b0}}})) ? {1'b1, {TF{1'b0}}} : tq[TF:0];
    always @(posedge clk) begin
        if (rst) begin
            left <= 0;
            out_valid <= 1'b0;
        end else begin
            out_valid <= busy;
            if (busy) out_t <= tc;
            if (load) begin
                d0 <= d0_in; d1 <= d1_in; d2 <= d2_in; d3 <= d3_in;
                left <= len;
            end else if (busy) begin
                d0 <= d0 + d1;
                d1 <= d1 + d2;
                d2 <= d2 + d3;
                left <= left - 1'b1;
            end
        end
    end
endmodule
