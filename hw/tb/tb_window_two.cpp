// tb_window_two — hw/rtl/window_two.v against `persp vectors --module window_two`
// (tb_window.h; "pixels" in its verdict are texels).   tb_window_two VECTORS [MIN_TEXELS]
#include "Vwindow_two.h"
#include "tb_window.h"

int main(int argc, char **argv) { return tb::run_window<Vwindow_two>("window_two", argc, argv); }
