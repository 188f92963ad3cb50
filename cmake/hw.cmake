# The Verilator testbenches of hw/ (docs/HARDWARE.md) as CTest tests with
# the label `hw`, each on >= 100 000 pixels of `persp vectors`; registered
# only when verilator is found, so that configuring never needs it.
# Included at the end of CMakeLists.txt (needs the persp_cli target).
find_program(PERSP_VERILATOR verilator)
# Not in the ThreadSanitizer build, which runs only the tests labelled
# threads.
if(PERSP_VERILATOR AND TARGET persp_cli AND PERSP_BUILD_TESTS AND NOT CMAKE_CROSSCOMPILING AND NOT PERSP_TSAN)
  set(PERSP_HW_DIR ${PROJECT_BINARY_DIR}/hw)
  # The ctest entry NAME: writes each of SETS' vector sets (`|` between
  # them) with `persp vectors`, joins them and runs the testbench TB on the
  # result, which must hold at least 100 000 pixels.
  function(persp_hw_test name sets tb)
    string(REPLACE "|" ";" parts "${sets}")
    set(gen "")
    set(k 0)
    foreach(opts ${parts})
      math(EXPR k "${k} + 1")
      string(APPEND gen "\"$1\" vectors ${opts} -o \"$2.${k}\" 2>/dev/null && ")
    endforeach()
    add_test(NAME ${name}
             COMMAND sh -c "${gen}cat \"$2\".* > \"$2\" && \"$3\" \"$2\" 100000"
                     ${name} $<TARGET_FILE:persp_cli> ${PERSP_HW_DIR}/${name}.ctest.vectors ${tb})
    set_tests_properties(${name} PROPERTIES LABELS hw TIMEOUT 300)
  endfunction()
  # Each module's vector sets, `|` between sets: the paths its model has
  # (ordinary pixels, re-seeds, leaving the format; see scripts/hw.sh).
  set(PERSP_HW_SETS_midpoint_int
      "--triangles 40|--texture-size 4096x4096 --triangles 10|--texture-size 4096x4096 --uv-range 20 --triangles 30 --seed 3|--method midpoint:int,edge --triangles 10")
  set(PERSP_HW_SETS_exact
      "--module exact --triangles 40|--module exact --texture-size 4096x4096 --triangles 20|--module exact --texture-size 4096x4096 --uv-range 20 --triangles 30 --seed 3")
  # The §4.8 windows and the §4.3 t_w modules (hw_models_shade.c).
  set(PERSP_HW_SETS_window_one
      "--module window_one --texture-size 4096x4096 --triangles 10|--module window_one --texture-size 1024x1024 --depth-ratio 30 --triangles 20 --seed 2")
  string(REPLACE "window_one" "window_two" PERSP_HW_SETS_window_two "${PERSP_HW_SETS_window_one}")
  foreach(m tw_exact tw_quadratic tw_pwquad tw_cubic)
    set(PERSP_HW_SETS_${m}
        "--module ${m} --depth-ratio 2 --triangles 30|--module ${m} --depth-ratio 8 --triangles 30 --seed 2|--module ${m} --depth-ratio 100 --triangles 30 --seed 3")
  endforeach()
  # The span datapaths (hw_models_span.c): 256 and 4096 texels, |t| beyond the format.
  foreach(m subdiv incremental quadratic cubic bezier)
    set(PERSP_HW_SETS_${m}
        "--module ${m} --triangles 40|--module ${m} --texture-size 4096x4096 --triangles 20|--module ${m} --texture-size 4096x4096 --uv-range 20 --triangles 30 --seed 3")
  endforeach()
  foreach(m midpoint_int exact window_one window_two tw_exact tw_quadratic tw_pwquad tw_cubic
          subdiv incremental quadratic cubic bezier)
    set(tb ${PERSP_HW_DIR}/obj_${m}/tb_${m})
    add_custom_command(
      OUTPUT ${tb}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${PERSP_HW_DIR}
      COMMAND ${PERSP_VERILATOR} --cc --exe --build -j 2 -O2 -Wall --Mdir ${PERSP_HW_DIR}/obj_${m}
              ${PROJECT_SOURCE_DIR}/hw/rtl/${m}.v ${PROJECT_SOURCE_DIR}/hw/tb/tb_${m}.cpp
              -y ${PROJECT_SOURCE_DIR}/hw/rtl -CFLAGS "-I${PROJECT_SOURCE_DIR}/hw/tb -O1" -o tb_${m} > ${PERSP_HW_DIR}/${m}.verilator.log
      DEPENDS ${PROJECT_SOURCE_DIR}/hw/rtl/${m}.v ${PROJECT_SOURCE_DIR}/hw/rtl/exact.v
              ${PROJECT_SOURCE_DIR}/hw/rtl/exact_stages.v ${PROJECT_SOURCE_DIR}/hw/tb/tb_${m}.cpp
              ${PROJECT_SOURCE_DIR}/hw/tb/tb_common.h ${PROJECT_SOURCE_DIR}/hw/tb/tb_fd.h ${PROJECT_SOURCE_DIR}/hw/tb/tb_uv.h
              ${PROJECT_SOURCE_DIR}/hw/tb/tb_tw.h ${PROJECT_SOURCE_DIR}/hw/tb/tb_window.h
      COMMENT "verilator: hw/rtl/${m}.v")
    add_custom_target(hw_tb_${m} ALL DEPENDS ${tb})
    persp_hw_test(hw_${m} "${PERSP_HW_SETS_${m}}" ${tb})
  endforeach()
  # midpoint_int's other settings, each on the default's vector sets: the
  # run-ahead divider (FALLBACK 1) at STEPS 4, the stalling design
  # (FALLBACK 0) at STEPS 4 and 1, and the divider alone (FALLBACK 2).
  foreach(variant "f1s4:-GSTEPS=4" "f0s4:-GFALLBACK=0:-GSTEPS=4" "f0s1:-GFALLBACK=0:-GSTEPS=1" "f2:-GFALLBACK=2")
    string(REPLACE ":" ";" vparts "${variant}")
    list(POP_FRONT vparts v)
    string(REPLACE ";" " " vtext "${vparts}")
    set(tbv ${PERSP_HW_DIR}/obj_midpoint_int_${v}/tb_midpoint_int)
    add_custom_command(
      OUTPUT ${tbv}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${PERSP_HW_DIR}
      COMMAND ${PERSP_VERILATOR} --cc --exe --build -j 2 -O2 -Wall ${vparts} --Mdir ${PERSP_HW_DIR}/obj_midpoint_int_${v}
              ${PROJECT_SOURCE_DIR}/hw/rtl/midpoint_int.v ${PROJECT_SOURCE_DIR}/hw/tb/tb_midpoint_int.cpp
              -CFLAGS "-I${PROJECT_SOURCE_DIR}/hw/tb -O1" -o tb_midpoint_int > ${PERSP_HW_DIR}/midpoint_int_${v}.verilator.log
      DEPENDS ${PROJECT_SOURCE_DIR}/hw/rtl/midpoint_int.v ${PROJECT_SOURCE_DIR}/hw/tb/tb_midpoint_int.cpp
              ${PROJECT_SOURCE_DIR}/hw/tb/tb_common.h
      COMMENT "verilator: hw/rtl/midpoint_int.v, ${vtext}")
    add_custom_target(hw_tb_midpoint_int_${v} ALL DEPENDS ${tbv})
    persp_hw_test(hw_midpoint_int_${v} "${PERSP_HW_SETS_midpoint_int}" ${tbv})
  endforeach()
  # subdiv at N = 8: the same RTL built with -GN=8, against `--module subdiv:8`.
  set(tb8 ${PERSP_HW_DIR}/obj_subdiv8/tb_subdiv)
  add_custom_command(
    OUTPUT ${tb8}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${PERSP_HW_DIR}
    COMMAND ${PERSP_VERILATOR} --cc --exe --build -j 2 -O2 -Wall -GN=8 --Mdir ${PERSP_HW_DIR}/obj_subdiv8
            ${PROJECT_SOURCE_DIR}/hw/rtl/subdiv.v ${PROJECT_SOURCE_DIR}/hw/tb/tb_subdiv.cpp
            -y ${PROJECT_SOURCE_DIR}/hw/rtl -CFLAGS "-I${PROJECT_SOURCE_DIR}/hw/tb -O1" -o tb_subdiv > ${PERSP_HW_DIR}/subdiv8.verilator.log
    DEPENDS ${PROJECT_SOURCE_DIR}/hw/rtl/subdiv.v ${PROJECT_SOURCE_DIR}/hw/rtl/exact_stages.v
            ${PROJECT_SOURCE_DIR}/hw/tb/tb_subdiv.cpp ${PROJECT_SOURCE_DIR}/hw/tb/tb_uv.h
            ${PROJECT_SOURCE_DIR}/hw/tb/tb_common.h
    COMMENT "verilator: hw/rtl/subdiv.v, N = 8")
  add_custom_target(hw_tb_subdiv8 ALL DEPENDS ${tb8})
  persp_hw_test(hw_subdiv8
                "--module subdiv:8 --triangles 40|--module subdiv:8 --texture-size 4096x4096 --uv-range 20 --triangles 30 --seed 3"
                ${tb8})
endif()
