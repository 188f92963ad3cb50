// tb_tw_quadratic — hw/rtl/tw_quadratic.v against `persp vectors --module
// tw_quadratic` (tb_tw.h).   tb_tw_quadratic VECTORS [MIN_PIXELS]
#include "Vtw_quadratic.h"
#include "tb_tw.h"

int main(int argc, char **argv)
{
    return tb::run_tw<Vtw_quadratic>("tw_quadratic", argc, argv, [](Vtw_quadratic &d, const tb::tw_span &s) {
        d.len = (uint8_t)s.n;
        d.d0_in = tb::port(s.a[0], 40), d.d1_in = tb::port(s.a[1], 40), d.d2_in = tb::port(s.a[2], 40);
    });
}
