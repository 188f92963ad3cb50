// tb_tw_exact — hw/rtl/tw_exact.v against `persp vectors --module tw_exact`
// (tb_tw.h); D0 = L*Q0 is the span's set-up.   tb_tw_exact VECTORS [MIN_PIXELS]
#include "Vtw_exact.h"
#include "tb_tw.h"

int main(int argc, char **argv)
{
    return tb::run_tw<Vtw_exact>("tw_exact", argc, argv, [](Vtw_exact &d, const tb::tw_span &s) {
        d.len = (uint8_t)s.n;
        d.Q0 = (uint16_t)s.a[0], d.Q1 = (uint16_t)s.a[1];
        d.D0 = (uint32_t)((s.n - 1) * s.a[0]);
    });
}
