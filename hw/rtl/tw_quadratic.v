// tw_quadratic — the perspective parameter t_w along a span by the quadratic
// approximation of [Romanyuk-PCF] §4.3 (nodes 0, L/2, L), evaluated by
// forward differences: per pixel two additions, no division. The span's
// differences d0, d1, d2 (DF fraction bits) are its set-up's, computed
// outside (three divisions per span); bit-exact with persp__hw_tw_run
// (src/analysis/hw_models_shade.c; format in docs/HARDWARE.md, "t_w").
// Output t_w * 2^TF, floor, clamped to [0, 1] (the polynomial overshoots by
// its error). One pixel per clock, latency 1.
module tw_quadratic #(
    parameter DW = 40,  // difference registers, signed
    parameter DF = 32,  // their fraction bits
    parameter TF = 16,  // output fraction bits
    parameter LW = 7    // len: 1..64 pixels
) (
    input  wire                 clk,
    input  wire                 rst,
    input  wire                 load,
    input  wire        [LW-1:0] len,
    input  wire signed [DW-1:0] d0_in,
    input  wire signed [DW-1:0] d1_in,
    input  wire signed [DW-1:0] d2_in,
    output wire                 ready,
    output reg                  out_valid,
    output reg         [TF:0]   out_t
);
    reg signed [DW-1:0] d0, d1, d2;
    reg [LW-1:0] left;
    wire busy = left != 0;
    // A load loses nothing when idle or while the span's last pixel goes out.
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
                left <= len;
            end else if (busy) begin
                d0 <= d0 + d1;
                d1 <= d1 + d2;
                left <= left - 1'b1;
            end
        end
    end
endmodule
