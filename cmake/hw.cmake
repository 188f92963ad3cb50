# The Verilator testbenches of hw/ (docs/HARDWARE.md) as CTest tests with
# the label `hw`, each on >= 100 000 pixels of `persp vectors`; registered
# only when verilator is found, so that configuring never needs it.
# Included at the end of CMakeLists.txt (needs the persp_cli target).
find_program(PERSP_VERILATOR verilator)
if(PERSP_VERILATOR AND TARGET persp_cli AND PERSP_BUILD_TESTS AND NOT CMAKE_CROSSCOMPILING)
  set(PERSP_HW_DIR ${PROJECT_BINARY_DIR}/hw)
  # Each module's vector sets, `|` between sets: the paths its model has
  # (ordinary pixels, re-seeds, leaving the format; see scripts/hw.sh).
  set(PERSP_HW_SETS_midpoint_int
      "--triangles 40|--texture-size 4096x4096 --triangles 10|--texture-size 4096x4096 --uv-range 20 --triangles 30 --seed 3|--method midpoint:int,edge --triangles 10")
  set(PERSP_HW_SETS_exact
      "--module exact --triangles 40|--module exact --texture-size 4096x4096 --triangles 20|--module exact --texture-size 4096x4096 --uv-range 20 --triangles 30 --seed 3")
  foreach(m midpoint_int exact)
    string(REPLACE "|" ";" parts "${PERSP_HW_SETS_${m}}")
    set(tb ${PERSP_HW_DIR}/obj_${m}/tb_${m})
    add_custom_command(
      OUTPUT ${tb}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${PERSP_HW_DIR}
      COMMAND ${PERSP_VERILATOR} --cc --exe --build -j 2 -O2 -Wall --Mdir ${PERSP_HW_DIR}/obj_${m}
              ${PROJECT_SOURCE_DIR}/hw/rtl/${m}.v ${PROJECT_SOURCE_DIR}/hw/tb/tb_${m}.cpp
              -CFLAGS "-I${PROJECT_SOURCE_DIR}/hw/tb -O1" -o tb_${m} > ${PERSP_HW_DIR}/${m}.verilator.log
      DEPENDS ${PROJECT_SOURCE_DIR}/hw/rtl/${m}.v ${PROJECT_SOURCE_DIR}/hw/tb/tb_${m}.cpp
              ${PROJECT_SOURCE_DIR}/hw/tb/tb_common.h
      COMMENT "verilator: hw/rtl/${m}.v")
    add_custom_target(hw_tb_${m} ALL DEPENDS ${tb})
    set(gen "")
    set(k 0)
    foreach(opts ${parts})
      math(EXPR k "${k} + 1")
      string(APPEND gen "\"$1\" vectors ${opts} -o \"$2.${k}\" 2>/dev/null && ")
    endforeach()
    add_test(NAME hw_${m}
             COMMAND sh -c "${gen}cat \"$2\".* > \"$2\" && \"$3\" \"$2\" 100000"
                     hw_${m} $<TARGET_FILE:persp_cli> ${PERSP_HW_DIR}/${m}.ctest.vectors ${tb})
    set_tests_properties(hw_${m} PROPERTIES LABELS hw TIMEOUT 300)
  endforeach()
endif()
