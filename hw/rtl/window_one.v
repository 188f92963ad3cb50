// window_one — the texels of the rotated footprint window of [Romanyuk-PCF]
// §4.8 walked with ONE linear (Bresenham) interpolator: it runs once from
// the load, one step per clock, and each step's direction bit (axial or
// diagonal) is remembered; rows are walked alternately forwards and
// backwards replaying the remembered steps, and row r moves to row r+1 by
// the (r+1)-th remembered step rotated by +90 degrees (the sides AB and AC
// have the same inclination, Fig. 4.16-4.18). Bit k is produced in the
// clock that first needs it (row 0's texel k, or the end of row k-1 when
// len = 1), so no clock waits. Bit-exact with persp__hw_window_one
// (src/analysis/hw_models_shade.c; docs/HARDWARE.md, "window"). One texel
// per clock, latency 1.
module window_one #(
    parameter XW = 24,   // texel coordinates, signed
    parameter SW = 6    // len, rows: 1..63
) (
    input  wire                 clk,
    input  wire                 rst,
    input  wire                 load,
    input  wire signed [XW-1:0] x0,
    input  wire signed [XW-1:0] y0,
    input  wire                 xmaj,   // the major axis is x
    input  wire                 sxn,    // sx = -1
    input  wire                 syn,    // sy = -1
    input  wire        [12:0]   dy,     // 0..DX
    input  wire        [SW-1:0] len,
    input  wire        [SW-1:0] rows,
    output wire                 ready,
    output reg                  out_valid,
    output reg  signed [XW-1:0] out_x,
    output reg  signed [XW-1:0] out_y
);
    reg signed [XW-1:0] x, y;
    reg [SW-1:0] i, r, n_len, n_rows, steps;
    reg [SW:0] g;             // the index of the bit the interpolator makes now
    reg [14:0] num;
    reg [13:0] dy2;
    reg xm, fwd, busy;
    reg signed [1:0] sx, sy;
    reg [(1<<SW)-1:0] pat;    // the remembered steps (bit 0 unused)

    wire last_i = i == n_len - 1'b1;
    wire last_r = r == n_rows - 1'b1;
    assign ready = !busy || (last_i && last_r);

    // The interpolator's step this clock: bit g.
    wire gen = busy && g <= {1'b0, steps};
    wire [14:0] num2 = num + {1'b0, dy2};
    wire fresh = num2 >= 15'd8192;
    // The step used this clock: within a row k = i+1 forwards, len-1-i
    // backwards; at a row's end k = r+1.
    wire [SW-1:0] kin = fwd ? i + 1'b1 : n_len - 1'b1 - i;
    wire [SW-1:0] k = last_i ? r + 1'b1 : kin;
    wire bit_k = (gen && {1'b0, k} == g) ? fresh : pat[k];
    wire signed [1:0] ddx = xm ? sx : (bit_k ? sx : 2'sd0);
    wire signed [1:0] ddy = xm ? (bit_k ? sy : 2'sd0) : sy;
    wire signed [XW-1:0] ddx_w = {{(XW-2){ddx[1]}}, ddx};
    wire signed [XW-1:0] ddy_w = {{(XW-2){ddy[1]}}, ddy};

    always @(posedge clk) begin
        if (rst) begin
            busy <= 1'b0;
            out_valid <= 1'b0;
        end else begin
            out_valid <= busy;
            if (busy) begin
                out_x <= x;
                out_y <= y;
            end
            if (load) begin
                x <= x0; y <= y0;
                xm <= xmaj;
                sx <= sxn ? -2'sd1 : 2'sd1;
                sy <= syn ? -2'sd1 : 2'sd1;
                dy2 <= {dy, 1'b0};
                num <= 15'd4096;
                n_len <= len; n_rows <= rows;
                steps <= (len > rows ? len : rows) - 1'b1;
                i <= 0; r <= 0; g <= 1;
                fwd <= 1'b1;
                pat <= 0;
                busy <= 1'b1;
            end else if (busy) begin
                if (gen) begin
                    num <= fresh ? num2 - 15'd8192 : num2;
                    pat[g[SW-1:0]] <= fresh;
                    g <= g + 1'b1;
                end
                if (!last_i) begin
                    x <= fwd ? x + ddx_w : x - ddx_w;
                    y <= fwd ? y + ddy_w : y - ddy_w;
                    i <= i + 1'b1;
                end else if (!last_r) begin
                    x <= x - ddy_w;
                    y <= y + ddx_w;
                    i <= 0;
                    r <= r + 1'b1;
                    fwd <= !fwd;
                end else begin
                    busy <= 1'b0;
                end
            end
        end
    end
endmodule
