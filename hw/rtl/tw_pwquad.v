// tw_pwquad — t_w along a span by the piecewise quadratic approximation of
// [Romanyuk-PCF] §4.3: pixels 0..m from the quadratic through 0, L/4, L/2,
// pixels m+1..L from the one through L/2, 3L/4, L (m = floor(L/2)), each by
// forward differences (two additions per pixel). Both pieces' differences
// are the span's set-up's (six divisions, outside); the second piece's are
// loaded into the registers after pixel m. Bit-exact with persp__hw_tw_run
// (src/analysis/hw_models_shade.c; docs/HARDWARE.md, "t_w"). One pixel per
// clock, latency 1.
module tw_pwquad #(
    parameter DW = 40,
    parameter DF = 32,
    parameter TF = 16,
    parameter LW = 7
) (
    input  wire                 clk,
    input  wire                 rst,
    input  wire                 load,
    input  wire        [LW-1:0] len,
    input  wire        [LW-2:0] m,
    input  wire signed [DW-1:0] d0_in,
    input  wire signed [DW-1:0] d1_in,
    input  wire signed [DW-1:0] d2_in,
    input  wire signed [DW-1:0] e0_in,
    input  wire signed [DW-1:0] e1_in,
    input  wire signed [DW-1:0] e2_in,
    output wire                 ready,
    output reg                  out_valid,
    output reg         [TF:0]   out_t
);
    reg signed [DW-1:0] d0, d1, d2, e0, e1, e2;
    reg [LW-1:0] left;
    reg [LW-2:0] pos, split;
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
                d0 <= d0_in; d1 <= d1_in; d2 <= d2_in;
                e0 <= e0_in; e1 <= e1_in; e2 <= e2_in;
                split <= m;
                pos <= 0;
                left <= len;
            end else if (busy) begin
                if (pos == split) begin
                    d0 <= e0; d1 <= e1; d2 <= e2;
                end else begin
                    d0 <= d0 + d1;
                    d1 <= d1 + d2;
                end
                pos <= pos + 1'b1;
                left <= left - 1'b1;
            end
        end
    end
endmodule
