// tb_quadratic — hw/rtl/quadratic.v against `persp vectors --module quadratic`
// (tb_fd.h; the format in docs/HARDWARE.md, "Vectors").
//
//   tb_quadratic VECTORS [MIN_PIXELS]
#include "Vquadratic.h"
#include "tb_fd.h"

static void load(Vquadratic &dut, const tb_fd::job<2> &j)
{
    dut.d0u = tb::port(j.d[0][0], tb_fd::DW);
    dut.d1u = tb::port(j.d[0][1], tb_fd::DW);
    dut.d2u = tb::port(j.d[0][2], tb_fd::DW);
    dut.d0v = tb::port(j.d[1][0], tb_fd::DW);
    dut.d1v = tb::port(j.d[1][1], tb_fd::DW);
    dut.d2v = tb::port(j.d[1][2], tb_fd::DW);
}

int main(int argc, char **argv)
{
    return tb_fd::run<Vquadratic, 2>("quadratic", argc, argv, load);
}
