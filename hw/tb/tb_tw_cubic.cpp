// tb_tw_cubic — hw/rtl/tw_cubic.v against `persp vectors --module tw_cubic`
// (tb_tw.h).   tb_tw_cubic VECTORS [MIN_PIXELS]
#include "Vtw_cubic.h"
#include "tb_tw.h"

int main(int argc, char **argv)
{
    return tb::run_tw<Vtw_cubic>("tw_cubic", argc, argv, [](Vtw_cubic &d, const tb::tw_span &s) {
        d.len = (uint8_t)s.n;
        d.d0_in = tb::port(s.a[0], 40), d.d1_in = tb::port(s.a[1], 40), d.d2_in = tb::port(s.a[2], 40);
        d.d3_in = tb::port(s.a[3], 40);
    });
}
