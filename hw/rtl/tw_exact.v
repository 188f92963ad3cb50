// tw_exact — the baseline of the t_w approximations ([Romanyuk-PCF] §4.3):
// t_w = N / D per pixel with N = k*Q1 and D = (L - k)*Q0 + k*Q1 stepped by
// additions (Q0, Q1: 1/w at the span's ends, normalised to QW bits) and one
// restoring division per pixel, pipelined one quotient bit a stage (N <= D,
// so t_w <= 1 and TF + 1 quotient bits). Bit-exact with persp__hw_tw_run
// (src/analysis/hw_models_shade.c; docs/HARDWARE.md, "t_w"). The span's
// start value D0 = L*Q0 is its set-up's. One pixel per clock.
module tw_exact #(
    parameter QW = 16,  // Q0, Q1 (unsigned, >= 1)
    parameter TF = 16,  // output fraction bits
    parameter LW = 7,   // len: 1..64
    parameter NW = 22   // N, D < 64 * 2^QW
) (
    input  wire          clk,
    input  wire          rst,
    input  wire          load,
    input  wire [LW-1:0] len,
    input  wire [QW-1:0] Q0,
    input  wire [QW-1:0] Q1,
    input  wire [NW-1:0] D0,
    output wire          ready,
    output reg           out_valid,
    output reg  [TF:0]   out_t
);
    reg [NW-1:0] N, D;
    reg [QW-1:0] q1;
    reg signed [QW:0] qd;
    reg [LW-1:0] left;
    wire busy = left != 0;
    assign ready = left <= 1;
    always @(posedge clk) begin
        if (rst) begin
            left <= 0;
        end else if (load) begin
            N <= 0;
            D <= D0;
            q1 <= Q1;
            qd <= $signed({1'b0, Q1}) - $signed({1'b0, Q0});
            left <= len;
        end else if (busy) begin
            N <= N + {{(NW-QW){1'b0}}, q1};
            D <= D + {{(NW-QW-1){qd[QW]}}, qd};
            left <= left - 1'b1;
        end
    end

    // Stage 0: the integer quotient bit (N >= D: t_w = 1); stages 1..TF:
    // one fraction bit each, remainder doubled and compared.
    wire [NW:0]   r  [0:TF];
    wire [NW-1:0] dv [0:TF];
    wire [TF:0]   q  [0:TF];
    wire          v  [0:TF];
    wire          z  [0:TF];
    reg  [NW:0]   r_q  [0:TF];
    reg  [NW-1:0] dv_q [0:TF];
    reg  [TF:0]   q_q  [0:TF];
    reg           v_q  [0:TF];
    reg           z_q  [0:TF];
    wire ge0 = N >= D;
    assign r[0]  = {1'b0, ge0 ? N - D : N};
    assign dv[0] = D;
    assign q[0]  = {{TF{1'b0}}, ge0};
    assign v[0]  = busy;
    assign z[0]  = D == 0;
    genvar j;
    generate
        for (j = 1; j <= TF; j = j + 1) begin : stage
            wire [NW:0] r2 = {r_q[j-1][NW-1:0], 1'b0};
            wire ge = r2 >= {1'b0, dv_q[j-1]};
            assign r[j]  = ge ? r2 - {1'b0, dv_q[j-1]} : r2;
            assign dv[j] = dv_q[j-1];
            assign q[j]  = {q_q[j-1][TF-1:0], ge};
            assign v[j]  = v_q[j-1];
            assign z[j]  = z_q[j-1];
        end
        for (j = 0; j <= TF; j = j + 1) begin : regs
            always @(posedge clk) begin
                if (rst) v_q[j] <= 1'b0;
                else v_q[j] <= v[j];
                r_q[j] <= r[j];
                dv_q[j] <= dv[j];
                q_q[j] <= q[j];
                z_q[j] <= z[j];
            end
        end
    endgenerate
    always @(posedge clk) begin
        if (rst) out_valid <= 1'b0;
        else out_valid <= v_q[TF];
        out_t <= z_q[TF] ? {(TF+1){1'b0}} : q_q[TF];
    end
endmodule
