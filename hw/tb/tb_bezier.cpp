// tb_bezier — hw/rtl/bezier.v against `persp vectors --module bezier`
// (tb_fd.h; the format in docs/HARDWARE.md, "Vectors").
//
//   tb_bezier VECTORS [MIN_PIXELS]
#include "Vbezier.h"
#include "tb_fd.h"

static void load(Vbezier &dut, const tb_fd::job<4> &j)
{
    dut.d0u = tb::port(j.d[0][0], tb_fd::DW);
    dut.d1u = tb::port(j.d[0][1], tb_fd::DW);
    dut.d2u = tb::port(j.d[0][2], tb_fd::DW);
    dut.d3u = tb::port(j.d[0][3], tb_fd::DW);
    dut.d4u = tb::port(j.d[0][4], tb_fd::DW);
    dut.d0v = tb::port(j.d[1][0], tb_fd::DW);
    dut.d1v = tb::port(j.d[1][1], tb_fd::DW);
    dut.d2v = tb::port(j.d[1][2], tb_fd::DW);
    dut.d3v = tb::port(j.d[1][3], tb_fd::DW);
    dut.d4v = tb::port(j.d[1][4], tb_fd::DW);
}

int main(int argc, char **argv)
{
    return tb_fd::run<Vbezier, 4>("bezier", argc, argv, load);
}
