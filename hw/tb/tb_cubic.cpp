// tb_cubic — hw/rtl/cubic.v against `persp vectors --module cubic`
// (tb_fd.h; the format in docs/HARDWARE.md, "Vectors").
//
//   tb_cubic VECTORS [MIN_PIXELS]
#include "Vcubic.h"
#include "tb_fd.h"

static void load(Vcubic &dut, const tb_fd::job<3> &j)
{
    dut.d0u = tb::port(j.d[0][0], tb_fd::DW);
    dut.d1u = tb::port(j.d[0][1], tb_fd::DW);
    dut.d2u = tb::port(j.d[0][2], tb_fd::DW);
    dut.d3u = tb::port(j.d[0][3], tb_fd::DW);
    dut.d0v = tb::port(j.d[1][0], tb_fd::DW);
    dut.d1v = tb::port(j.d[1][1], tb_fd::DW);
    dut.d2v = tb::port(j.d[1][2], tb_fd::DW);
    dut.d3v = tb::port(j.d[1][3], tb_fd::DW);
}

int main(int argc, char **argv)
{
    return tb_fd::run<Vcubic, 3>("cubic", argc, argv, load);
}
