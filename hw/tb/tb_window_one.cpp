// tb_window_one — hw/rtl/window_one.v against `persp vectors --module window_one`
// (tb_window.h; "pixels" in its verdict are texels).   tb_window_one VECTORS [MIN_TEXELS]
#include "Vwindow_one.h"
#include "tb_window.h"

int main(int argc, char **argv) { return tb::run_window<Vwindow_one>("window_one", argc, argv); }
