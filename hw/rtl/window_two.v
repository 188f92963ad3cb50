// window_two — the baseline of [Romanyuk-PCF] §4.8's claim: the rotated
// footprint window walked with TWO linear (Bresenham) interpolators, one
// along the rows (restarted at each row's start) and one along the column
// of row starts (one step a row), rows in raster order. The same texels as
// window_one (persp vectors checks the sets); bit-exact with
// persp__hw_window_two (src/analysis/hw_models_shade.c; docs/HARDWARE.md,
// "window"). One texel per clock, latency 1.
module window_two #(
    parameter XW = 24,
    parameter SW = 6
) (
    input  wire                 clk,
    input  wire                 rst,
    input  wire                 load,
    input  wire signed [XW-1:0] x0,
    input  wire signed [XW-1:0] y0,
    input  wire                 xmaj,
    input  wire                 sxn,
    input  wire                 syn,
    input  wire        [12:0]   dy,
    input  wire        [SW-1:0] len,
    input  wire        [SW-1:0] rows,
    output wire                 ready,
    output reg                  out_valid,
    output reg  signed [XW-1:0] out_x,
    output reg  signed [XW-1:0] out_y
);
    reg signed [XW-1:0] x, y, xr, yr;
    reg [SW-1:0] i, r, n_len, n_rows;
    reg [14:0] numi, numr;
    reg [13:0] dy2;
    reg xm, busy;
    reg signed [1:0] sx, sy;

    wire last_i = i == n_len - 1'b1;
    wire last_r = r == n_rows - 1'b1;
    assign ready = !busy || (last_i && last_r);

    // The row's interpolator and the column's.
    wire [14:0] ni2 = numi + {1'b0, dy2};
    wire bi = ni2 >= 15'd8192;
    wire [14:0] nr2 = numr + {1'b0, dy2};
    wire br = nr2 >= 15'd8192;
    wire signed [1:0] ix = xm ? sx : (bi ? sx : 2'sd0);
    wire signed [1:0] iy = xm ? (bi ? sy : 2'sd0) : sy;
    wire signed [1:0] rx = xm ? sx : (br ? sx : 2'sd0);
    wire signed [1:0] ry = xm ? (br ? sy : 2'sd0) : sy;
    wire signed [XW-1:0] ix_w = {{(XW-2){ix[1]}}, ix};
    wire signed [XW-1:0] iy_w = {{(XW-2){iy[1]}}, iy};
    wire signed [XW-1:0] rx_w = {{(XW-2){rx[1]}}, rx};
    wire signed [XW-1:0] ry_w = {{(XW-2){ry[1]}}, ry};
    wire signed [XW-1:0] nxr = xr - ry_w;
    wire signed [XW-1:0] nyr = yr + rx_w;

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
                x <= x0; y <= y0; xr <= x0; yr <= y0;
                xm <= xmaj;
                sx <= sxn ? -2'sd1 : 2'sd1;
                sy <= syn ? -2'sd1 : 2'sd1;
                dy2 <= {dy, 1'b0};
                numi <= 15'd4096; numr <= 15'd4096;
                n_len <= len; n_rows <= rows;
                i <= 0; r <= 0;
                busy <= 1'b1;
            end else if (busy) begin
                if (!last_i) begin
                    numi <= bi ? ni2 - 15'd8192 : ni2;
                    x <= x + ix_w;
                    y <= y + iy_w;
                    i <= i + 1'b1;
                end else if (!last_r) begin
                    numr <= br ? nr2 - 15'd8192 : nr2;
                    numi <= 15'd4096;
                    xr <= nxr; yr <= nyr;
                    x <= nxr; y <= nyr;
                    i <= 0;
                    r <= r + 1'b1;
                end else begin
                    busy <= 1'b0;
                end
            end
        end
    end
endmodule
