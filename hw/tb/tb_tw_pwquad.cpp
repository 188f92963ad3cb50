// tb_tw_pwquad — hw/rtl/tw_pwquad.v against `persp vectors --module
// tw_pwquad` (tb_tw.h).   tb_tw_pwquad VECTORS [MIN_PIXELS]
#include "Vtw_pwquad.h"
#include "tb_tw.h"

int main(int argc, char **argv)
{
    return tb::run_tw<Vtw_pwquad>("tw_pwquad", argc, argv, [](Vtw_pwquad &d, const tb::tw_span &s) {
        d.len = (uint8_t)s.n, d.m = (uint8_t)s.m;
        d.d0_in = tb::port(s.a[0], 40), d.d1_in = tb::port(s.a[1], 40), d.d2_in = tb::port(s.a[2], 40);
        d.e0_in = tb::port(s.b[0], 40), d.e1_in = tb::port(s.b[1], 40), d.e2_in = tb::port(s.b[2], 40);
    });
}
