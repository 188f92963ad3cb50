// cubic — [Romanyuk-PCF]
// §4.4: the cubic through the span's ends and the points dividing it in
// thirds, stepped by forward differences: three accumulators per
// coordinate after the value.
//
// The per-span fit (the float method's, in double) and the quantisation of
// its differences d0..d3 to FRAC fraction bits are the set-up, outside this
// module: persp__hw_fd_setup (src/analysis/hw_models_span.c), written into
// the vectors (`persp vectors --module cubic`). Here only additions: per
// pixel d_i += d_(i+1), all in parallel (each reads the old d_(i+1)), which
// is persp__hw_fd_pixel bit for bit. Output t·2^8 = d0 >> (FRAC - 8), TOW
// bits, like exact's. One pixel per clock, spans back to back: `ready` (a
// load in this cycle loses nothing) while the last pixel goes out.
module cubic #(
    parameter DW   = 50,  // d0..d3, signed: |d_j| < 2^16 texels with FRAC fraction bits
    parameter FRAC = 32,
    parameter TOW  = 25,  // out_tu, out_tv: texels * 2^8
    parameter LW   = 7
) (
    input  wire                  clk,
    input  wire                  rst,
    input  wire                  load,
    input  wire signed [DW-1:0]  d0u, d1u, d2u, d3u,
    input  wire signed [DW-1:0]  d0v, d1v, d2v, d3v,
    input  wire        [LW-1:0]  len,
    output wire                  ready,
    output reg                   out_valid,
    output reg  signed [TOW-1:0] out_tu,
    output reg  signed [TOW-1:0] out_tv
);
    // d0's bits below FRAC - 8 and above the output are the model's too (it
    // wraps at DW bits), read by nothing.
    /* verilator lint_off UNUSEDSIGNAL */
    reg signed [DW-1:0] U0, V0;
    /* verilator lint_on UNUSEDSIGNAL */
    reg signed [DW-1:0] U1, U2, U3;
    reg signed [DW-1:0] V1, V2, V3;
    reg        [LW-1:0] left;
    assign ready = left <= 1;

    always @(posedge clk) begin
        if (rst) begin
            left <= 0;
            out_valid <= 0;
        end else begin
            if (load) begin
                U0 <= d0u; U1 <= d1u; U2 <= d2u; U3 <= d3u;
                V0 <= d0v; V1 <= d1v; V2 <= d2v; V3 <= d3v;
                left <= len;
            end else if (left != 0) begin
                U0 <= U0 + U1; U1 <= U1 + U2; U2 <= U2 + U3;
                V0 <= V0 + V1; V1 <= V1 + V2; V2 <= V2 + V3;
                left <= left - 1'b1;
            end
            out_valid <= left != 0;
            out_tu <= U0[FRAC+TOW-9:FRAC-8];
            out_tv <= V0[FRAC+TOW-9:FRAC-8];
        end
    end
endmodule
