#!/usr/bin/env bash
# The RTL of hw/rtl verified and synthesized (docs/HARDWARE.md):
# for each module, Verilator builds its testbench (hw/tb), the built persp
# writes its vectors (`persp vectors --module M`), the testbench compares
# every pixel; then Yosys synthesizes it for the iCE40 UP5K and nextpnr
# places and routes it (logic cells, SB_MAC16, block RAM, Fmax), and Yosys +
# ABC technology-independently (transistor estimate, logic depth). Every
# number of out/hw/summary.json and summary.md is read from the tools'
# output of this run.
#
#   scripts/hw.sh [BUILD]      BUILD: persp's build folder (default build)
#   HW_SMALL=1                 fewer vectors (still >= 100 000 pixels a module)
#   HW_NO_SYNTH=1              testbenches only
#   HW_MODULES="exact"         a subset
#   HW_MIDPOINT_VARIANTS="0:2 1:8"  midpoint_int's FALLBACK:STEPS settings measured besides
#                              the default (default "0:4 2:1"; docs/HARDWARE.md's
#                              table adds "1:4 0:1")
#   HW_PNR_TIMEOUT=300         seconds before nextpnr is stopped (a design that fills the device)
#   HW_MODULE_ALONE=1          also pack each module synthesized alone (ice40_lc_module_alone)
set -eu
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
persp="$build/persp"
work="$build/hw"
out="$root/out/hw"
mkdir -p "$work" "$out"
[ -x "$persp" ] || { echo "hw: $persp not built" >&2; exit 1; }
for t in verilator yosys nextpnr-ice40; do
    command -v "$t" >/dev/null || { echo "hw: $t missing (bash scripts/deps.sh --hw)" >&2; exit 1; }
done
modules="${HW_MODULES:-midpoint_int exact window_one window_two tw_exact tw_quadratic tw_pwquad tw_cubic subdiv incremental quadratic cubic bezier}"
scale=1
[ "${HW_SMALL:-0}" = 1 ] && scale=0

# vectors MODULE FILE: the module's vector sets, one file (the testbenches
# read concatenated sets). Each set is one of the integer model's paths.
vectors() {
    local m="$1" f="$2" n
    : >"$f"
    if [ "$m" = midpoint_int ]; then
        n=$((scale ? 80 : 30))
        "$persp" vectors --triangles "$n" -o "$f.1" 2>/dev/null                           # ordinary pixels
        "$persp" vectors --method midpoint:int,edge --depth-ratio 100 --triangles "$n" -o "$f.2" 2>/dev/null
        "$persp" vectors --texture-size 4096x4096 --triangles 10 -o "$f.3" 2>/dev/null   # re-seeds
        "$persp" vectors --texture-size 4096x4096 --uv-range 20 --triangles 30 --seed 3 -o "$f.4" 2>/dev/null  # fallbacks
        "$persp" vectors --texture-size 4096x4096 --uv-range 100 --triangles 4 -o "$f.5" 2>/dev/null  # spans outside
        cat "$f".[1-5] >"$f"
    elif [ "${m#window_}" != "$m" ]; then
        # Minified footprints (the window exists): 4096 texels, and 1024 at
        # depth ratio 30 (longer, rotated windows).
        n=$((scale ? 10 : 6))
        "$persp" vectors --module "$m" --texture-size 4096x4096 --triangles "$n" -o "$f.1" 2>/dev/null
        "$persp" vectors --module "$m" --texture-size 1024x1024 --depth-ratio 30 --triangles $((2 * n)) --seed 2 \
            -o "$f.2" 2>/dev/null
        cat "$f".[12] >"$f"
    elif [ "${m#tw_}" != "$m" ]; then
        # t_w depends on the span's depth ratio only: 2, 8 and 100.
        n=$((scale ? 60 : 30))
        local k=1 d
        for d in 2 8 100; do
            "$persp" vectors --module "$m" --depth-ratio $d --triangles "$n" --seed $k -o "$f.err$k" 2>/dev/null
            k=$((k + 1))
        done
        cat "$f".err[1-3] >"$f"
    else
        n=$((scale ? 60 : 25))
        local k=1 d t
        for t in 256x256 4096x4096; do
            for d in 2 8; do
                "$persp" vectors --module "$m" --texture-size $t --depth-ratio $d --triangles "$n" --seed $k \
                    -o "$f.err$k" 2>/dev/null
                k=$((k + 1))
            done
        done
        # |t| beyond the format's 2^15 texels: the out-of-range flag.
        "$persp" vectors --module "$m" --texture-size 4096x4096 --uv-range 20 --triangles 30 --seed 3 -o "$f.6" 2>/dev/null
        cat "$f".err* "$f.6" >"$f"
    fi
}

# The Verilog a module is read from: its file, and the modules it
# instantiates (exact's stages, in exact, subdiv and incremental's chains).
rtl_files() {
    case "$1" in
        exact | subdiv) echo "$root/hw/rtl/$1.v $root/hw/rtl/exact_stages.v" ;;
        incremental) echo "$root/hw/rtl/$1.v $root/hw/rtl/exact.v $root/hw/rtl/exact_stages.v" ;;
        *) echo "$root/hw/rtl/$1.v" ;;
    esac
}

# tb MODULE [VARIANT "PARAM=VALUE ..."]: the testbench in obj_MODULE
# (obj_MODULE_VARIANT built with -GPARAM=VALUE for each).
tb() {
    local m="$1" v="${2:+_$2}" g="" p
    for p in ${3:-}; do g="$g -G$p"; done
    verilator --cc --exe --build -j 2 -O2 -Wall $g --Mdir "$work/obj_$m$v" "$root/hw/rtl/$m.v" "$root/hw/tb/tb_$m.cpp" \
        -y "$root/hw/rtl" -CFLAGS "-I$root/hw/tb -O1" -o "tb_$m" >"$work/$m$v.verilator.log" 2>&1 ||
        { cat "$work/$m$v.verilator.log" >&2; return 1; }
}

# synth MODULE [VARIANT "PARAM=VALUE ..."]: into syn_MODULE (syn_MODULE_VARIANT
# with the parameters set by chparam).
synth() {
    local m="$1" v="${2:+_$2}" cp="" p
    local d="$work/syn_$m$v"
    for p in ${3:-}; do cp="$cp chparam -set ${p%%=*} ${p#*=} $m;"; done
    mkdir -p "$d"
    yosys -q -p "read_verilog $(rtl_files $m); $cp hierarchy -top $m; proc; write_json $d/ports.json" >"$d/ports.log" 2>&1
    python3 "$root/hw/ooc_wrap.py" "$d/ports.json" "$m" "$d/${m}_ooc.v" >"$d/wrapper_ffs"
    yosys -p "read_verilog $(rtl_files $m) $d/${m}_ooc.v; $cp synth_ice40 -dsp -top ${m}_ooc -json $d/ice40.json" \
        >"$d/ice40.log" 2>&1
    # HW_MODULE_ALONE=1: the module also synthesized by itself and packed
    # into logic cells (no placement: its ports are more than the pins), a
    # cross-check of ice40_lc_module (docs/HARDWARE.md).
    rm -f "$d/pack.log"
    if [ "${HW_MODULE_ALONE:-0}" = 1 ]; then
        yosys -p "read_verilog $(rtl_files $m); $cp synth_ice40 -dsp -top $m -json $d/module.json" >"$d/module.log" 2>&1
        nextpnr-ice40 --up5k --package sg48 --json "$d/module.json" --pack-only >"$d/pack.log" 2>&1 || true
    fi
    # A module that needs more than the UP5K has (8 SB_MAC16, 5280 LCs) is a
    # result, not a failure of the flow: summary.json then says so (ice40_fits
    # false). One that fills the device may route for a very long time: after
    # HW_PNR_TIMEOUT seconds it counts as not routed.
    rm -f "$d/pnr.json"
    local rc=0 lim="${HW_PNR_TIMEOUT:-300}"
    timeout "$lim" nextpnr-ice40 --up5k --package sg48 --json "$d/ice40.json" --freq 12 --seed 1 \
        --report "$d/pnr.json" >"$d/pnr.log" 2>&1 || rc=$?
    [ "$rc" != 124 ] || echo "ERROR: not routed within $lim s (HW_PNR_TIMEOUT)" >>"$d/pnr.log"
    [ -e "$d/pnr.json" ] || echo "hw: $m: not placed and routed on the iCE40 UP5K ($d/pnr.log)"
    yosys -p "read_verilog $(rtl_files $m); $cp synth -flatten -top $m; abc; opt_clean; stat -tech cmos; ltp -noff" \
        >"$d/generic.log" 2>&1
}

# midpoint_int's default FALLBACK:STEPS (its parameters), and the other
# settings measured: testbench on all sets and on the first, synthesis.
mp_param() { sed -n "s/^ *parameter $1 *= *\([0-9]*\).*/\1/p" "$root/hw/rtl/midpoint_int.v"; }
mp_default="$(mp_param FALLBACK):$(mp_param STEPS)"
mp_sweep=""
for k in ${HW_MIDPOINT_VARIANTS-0:4 2:1}; do [ "$k" = "$mp_default" ] || mp_sweep="$mp_sweep $k"; done

status=0
for m in $modules; do
    echo "hw: $m: testbench"
    tb "$m"
    vectors "$m" "$work/$m.vectors"
    if "$work/obj_$m/tb_$m" "$work/$m.vectors" 100000 >"$work/$m.tb.log"; then :; else status=1; fi
    tail -1 "$work/$m.tb.log"
    # Throughput on ordinary triangles (256 texels) apart from the edge cases.
    if [ "$m" = midpoint_int ]; then
        "$work/obj_$m/tb_$m" "$work/$m.vectors.1" >"$work/$m.tb_plain.log" || status=1
        for k in $mp_sweep; do
            v="f${k%%:*}s${k#*:}" p="FALLBACK=${k%%:*} STEPS=${k#*:}"
            echo "hw: $m: $p"
            tb "$m" "$v" "$p"
            "$work/obj_${m}_$v/tb_$m" "$work/$m.vectors" 100000 >"$work/${m}_$v.tb.log" || status=1
            "$work/obj_${m}_$v/tb_$m" "$work/$m.vectors.1" >"$work/${m}_$v.tb_plain.log" || status=1
            [ "${HW_NO_SYNTH:-0}" = 1 ] || synth "$m" "$v" "$p"
        done
    fi
    # subdiv at N = 8 as well: the same RTL built with -GN=8 against `--module subdiv:8`.
    if [ "$m" = subdiv ]; then
        verilator --cc --exe --build -j 2 -O2 -Wall -GN=8 --Mdir "$work/obj_subdiv8" "$root/hw/rtl/subdiv.v" \
            "$root/hw/tb/tb_subdiv.cpp" -y "$root/hw/rtl" -CFLAGS "-I$root/hw/tb -O1" -o tb_subdiv >"$work/subdiv8.verilator.log" 2>&1 ||
            { cat "$work/subdiv8.verilator.log" >&2; status=1; }
        vectors subdiv:8 "$work/subdiv8.vectors"
        "$work/obj_subdiv8/tb_subdiv" "$work/subdiv8.vectors" 100000 >"$work/subdiv8.tb.log" || status=1
        tail -1 "$work/subdiv8.tb.log"
    fi
    if [ "${HW_NO_SYNTH:-0}" != 1 ]; then
        echo "hw: $m: synthesis"
        synth "$m"
    fi
done
# What one SB_MAC16 (16 x 16 multiply) costs in logic cells when built from
# LUTs: the DSP equivalent of the area plot (hw/plot_pareto.py).
printf 'module mul16(input clk, input [15:0] a, b, output reg [31:0] p);\n always @(posedge clk) p <= a * b;\nendmodule\n' \
    >"$work/mul16.v"
[ "${HW_NO_SYNTH:-0}" = 1 ] || yosys -p "read_verilog $work/mul16.v; synth_ice40 -top mul16" >"$work/mul16.log" 2>&1
# midpoint_int's error is persp's own measurement of midpoint:int.
"$persp" accuracy --case random-triangles --method midpoint:int --json >"$work/midpoint_int.accuracy.json"

python3 - "$root" "$work" "$out" "$modules" "${HW_NO_SYNTH:-0}" "$mp_default" "$mp_sweep" <<'PY'
import json, os, re, subprocess, sys
root, work, out, modules, nosynth = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4].split(), sys.argv[5] == "1"
# midpoint_int's settings as (FALLBACK, STEPS).
mp_default = tuple(int(x) for x in sys.argv[6].split(":"))
mp_sweep = [tuple(int(x) for x in k.split(":")) for k in sys.argv[7].split()]
method = {"midpoint_int": "midpoint:int", "exact": "exact (hw fixed point)"}
# The span datapaths (hw_models_span.c) and the float method each implements.
span = {"subdiv": "subdiv:16", "incremental": "incremental:bidir", "quadratic": "quadratic", "cubic": "cubic",
        "bezier": "bezier:quadt"}
method.update({k: v + " (hw fixed point)" for k, v in span.items()})

def grab(path, pattern, conv=float, default=None):
    try:
        m = re.findall(pattern, open(path).read())
    except OSError:
        return default
    return conv(m[-1]) if m else default

def synth_numbers(d):
    """The iCE40 and technology-independent figures of one synthesis folder."""
    r = {}
    if not os.path.exists(os.path.join(d, "pnr.json")):
        # Placement failed: the device's limit it met, from nextpnr's log; the
        # cells synth_ice40 asked for, from Yosys's.
        r["ice40_fits"] = False
        r["ice40_pnr_error"] = grab(os.path.join(d, "pnr.log"), r"ERROR: (.*)", str)
        r["ice40_dsp_needed"] = grab(os.path.join(d, "ice40.log"), r"SB_MAC16\s+(\d+)", int)
        # The logic cells after packing, of the 5280, where nextpnr got that far.
        r["ice40_lc_needed"] = grab(os.path.join(d, "pnr.log"), r"ICESTORM_LC:\s+(\d+)/", int)
        r["ice40_wrapper_ffs"] = int(open(os.path.join(d, "wrapper_ffs")).read())
    else:
        pnr = json.load(open(os.path.join(d, "pnr.json")))
        u = pnr["utilization"]
        r["ice40_fits"] = True
        r["ice40_lc"] = u["ICESTORM_LC"]["used"]
        r["ice40_dsp"] = u.get("ICESTORM_DSP", {}).get("used", 0)
        r["ice40_bram"] = u.get("ICESTORM_RAM", {}).get("used", 0)
        r["ice40_wrapper_ffs"] = int(open(os.path.join(d, "wrapper_ffs")).read())
        r["fmax_mhz"] = round(min(v["achieved"] for v in pnr["fmax"].values()), 2)
    # The module's own logic cells: each of the wrapper's flip-flops takes
    # an LC of its own (the input chain's with no LUT, each output capture
    # with its 2:1 LUT), which nextpnr never packs with the module's logic,
    # so they are subtracted exactly; from the placed count, or after
    # packing where the design was not placed (docs/HARDWARE.md).
    lc = r.get("ice40_lc", r.get("ice40_lc_needed"))
    r["ice40_lc_module"] = lc - r["ice40_wrapper_ffs"] if lc is not None else None
    r["ice40_dsp_module"] = r.get("ice40_dsp", r.get("ice40_dsp_needed"))
    # HW_MODULE_ALONE=1: the module synthesized and packed by itself.
    r["ice40_lc_module_alone"] = grab(os.path.join(d, "pack.log"), r"ICESTORM_LC:\s+(\d+)/", int)
    r["ice40_dsp_module_alone"] = grab(os.path.join(d, "pack.log"), r"ICESTORM_DSP:\s+(\d+)/", int)
    g = os.path.join(d, "generic.log")
    r["cmos_transistors"] = grab(g, r"Estimated number of transistors:\s+(\d+)", int)
    r["logic_depth"] = grab(g, r"Longest topological path in \S+ \(length=(\d+)\)", int)
    r["ice40_lut4_wrapped"] = grab(os.path.join(d, "ice40.log"), r"SB_LUT4\s+(\d+)", int)
    return r

rows = []
for m in modules:
    log = os.path.join(work, m + ".tb.log")
    r = {"module": m, "method": method.get(m, m), "rtl": "hw/rtl/%s.v" % m, "top": m}
    r["vectors_checked"] = grab(log, r"pixels (\d+) mismatches", int)
    r["mismatches"] = grab(log, r"mismatches (\d+)", int)
    if m.startswith("window_") or m.startswith("tw_"):
        # hw/rtl/window_*.v, tw_*.v: errors from the vectors' closing lines.
        r["latency_cycles"] = grab(log, r"latency (\d+) cycles", int)
        r["pixels_per_clock"] = grab(log, r"([\d.]+) pixels per clock")
        sets = [os.path.join(work, "%s.vectors.%s" % (m, k)) for k in ("1", "2", "err1", "err2", "err3")]
        sets = [f for f in sets if os.path.exists(f)]
        if m.startswith("window_"):
            r["error_unit"] = "texel position"
            r["max_error"] = max(grab(f, r"max texel position error ([\d.]+)") for f in sets)
            r["windows_differing_from_other_traversal"] = sum(
                grab(f, r"(\d+) windows whose texel set differs", int) for f in sets)
        else:
            r["error_unit"] = "t_w"
            r["max_error"] = max(grab(f, r"max \|dtw\| model ([\d.]+)") for f in sets)
            r["max_error_float_method"] = max(grab(f, r"max \|dtw\| float method ([\d.]+)") for f in sets)
            r["max_error_tw_by_depth_ratio"] = {
                d: grab(os.path.join(work, "%s.vectors.err%d" % (m, k)), r"max \|dtw\| model ([\d.]+)")
                for k, d in ((1, "2"), (2, "8"), (3, "100"))}
    elif m == "exact" or m in span:
        r["latency_cycles"] = grab(log, r"latency (\d+) cycles", int)
        r["pixels_per_clock"] = grab(log, r"([\d.]+) pixels per clock")
        errs = []
        for k in range(1, 5):
            f = os.path.join(work, "%s.vectors.err%d" % (m, k))
            errs += [grab(f, r"max \|du\| ([\d.]+)"), grab(f, r"max \|dv\| ([\d.]+)")]
        r["max_error_texels"] = max(e for e in errs if e is not None)
        r["max_error_texels_256"] = max(errs[0:4])
        r["max_error_texels_4096"] = max(errs[4:8])
        # The float method's own error on the same pixels (the vectors' last line):
        # [256 ħ=2, 256 ħ=8, 4096 ħ=2, 4096 ħ=8] for the model and the method.
        sets = [os.path.join(work, "%s.vectors.err%d" % (m, k)) for k in range(1, 5)]
        if m in span:
            pair = lambda f, p: max(grab(f, p + r"u ([\d.]+)"), grab(f, p + r"u [\d.]+, v ([\d.]+)"))
            r["max_error_texels_by_set"] = [max(errs[2 * k], errs[2 * k + 1]) for k in range(4)]
            r["float_method"] = span[m]
            r["float_max_error_texels_by_set"] = [pair(f, r"same pixels: ") for f in sets]
            if m == "subdiv":
                n8 = [os.path.join(work, "subdiv8.vectors.err%d" % k) for k in range(1, 5)]
                r["n8_vectors_checked"] = grab(os.path.join(work, "subdiv8.tb.log"), r"pixels (\d+) mismatches", int)
                r["n8_mismatches"] = grab(os.path.join(work, "subdiv8.tb.log"), r"mismatches (\d+)", int)
                r["n8_max_error_texels_by_set"] = [max(grab(f, r"max \|du\| ([\d.]+)"), grab(f, r"max \|dv\| ([\d.]+)"))
                                                   for f in n8]
                r["n8_float_max_error_texels_by_set"] = [pair(f, r"same pixels: ") for f in n8]
    else:
        # midpoint_int: measured by the testbench (FALLBACK 0 stalls).
        r["latency_cycles"] = grab(log, r"latency (\d+) cycles", int)
        plain = os.path.join(work, m + ".tb_plain.log")
        r["pixels_per_clock"] = grab(plain, r"([\d.]+) pixels per clock")
        r["cycles_per_pixel_per_coordinate"] = grab(plain, r"([\d.]+) cycles per pixel per coordinate")
        r["pixels_per_clock_all_vectors"] = grab(log, r"([\d.]+) pixels per clock")
        acc = json.load(open(os.path.join(work, "midpoint_int.accuracy.json")))
        vals = []
        def walk(o):
            if isinstance(o, dict):
                if o.get("method") == "midpoint:int" and o.get("hbar") in (2, 8):
                    vals.extend([o["max_u"], o["max_v"]])
                for v in o.values():
                    walk(v)
            elif isinstance(o, list):
                for v in o:
                    walk(v)
        walk(acc)
        r["max_error_texels"] = max(vals) if vals else None
    if not nosynth:
        r.update(synth_numbers(os.path.join(work, "syn_" + m)))
    if m == "midpoint_int":
        # The lattice steps searched per clock and the fallback: the default
        # and the other settings measured (docs/HARDWARE.md).
        r["fallback"], r["steps_per_clock"] = mp_default
        keys = ("latency_cycles", "pixels_per_clock", "pixels_per_clock_all_vectors", "cycles_per_pixel_per_coordinate",
                "vectors_checked", "mismatches", "ice40_fits", "ice40_lc", "ice40_lc_needed", "ice40_pnr_error",
                "ice40_dsp", "ice40_wrapper_ffs", "ice40_lc_module", "ice40_dsp_module", "fmax_mhz", "cmos_transistors",
                "logic_depth")
        head = ("fallback", "steps_per_clock")
        sweep = [dict(zip(head, mp_default), **{k: r.get(k) for k in keys})]
        for f, k in mp_sweep:
            v = "%s_f%ds%d" % (m, f, k)
            log_all, log_plain = os.path.join(work, v + ".tb.log"), os.path.join(work, v + ".tb_plain.log")
            e = {"fallback": f, "steps_per_clock": k,
                 "latency_cycles": grab(log_all, r"latency (\d+) cycles", int),
                 "pixels_per_clock": grab(log_plain, r"([\d.]+) pixels per clock"),
                 "pixels_per_clock_all_vectors": grab(log_all, r"([\d.]+) pixels per clock"),
                 "cycles_per_pixel_per_coordinate": grab(log_plain, r"([\d.]+) cycles per pixel per coordinate"),
                 "vectors_checked": grab(log_all, r"pixels (\d+) mismatches", int),
                 "mismatches": grab(log_all, r"mismatches (\d+)", int)}
            if not nosynth:
                e.update(synth_numbers(os.path.join(work, "syn_" + v)))
            sweep.append({key: e.get(key) for key in head + keys})
        r["steps_sweep"] = sorted(sweep, key=lambda e: (e["fallback"], e["steps_per_clock"]))
    rows.append(r)

ver = {}
for tool, args in (("verilator", ["--version"]), ("yosys", ["-V"]), ("nextpnr-ice40", ["--version"])):
    p = subprocess.run([tool] + args, capture_output=True, text=True)
    ver[tool] = (p.stdout + p.stderr).strip().splitlines()[0]
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
dspeq = grab(os.path.join(work, "mul16.log"), r"SB_LUT4\s+(\d+)", int)
json.dump({"tools": ver, "cpu": cpu, "ice40_dsp_lut4_equivalent": dspeq, "modules": rows}, open(os.path.join(out, "summary.json"), "w"), indent=2)

cols = ["module", "ice40_lc", "ice40_lc_module", "ice40_dsp", "ice40_bram", "fmax_mhz", "cmos_transistors", "logic_depth",
        "latency_cycles", "pixels_per_clock", "vectors_checked", "mismatches", "max_error_texels", "max_error", "error_unit"]
md = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
for r in rows:
    md.append("| " + " | ".join("-" if r.get(c) is None else str(r.get(c)) for c in cols) + " |")
for r in rows:
    if r.get("steps_sweep"):
        sc = ["fallback", "steps_per_clock", "latency_cycles", "pixels_per_clock", "pixels_per_clock_all_vectors",
              "ice40_lc", "ice40_lc_needed", "ice40_lc_module", "ice40_dsp", "fmax_mhz", "cmos_transistors",
              "logic_depth", "mismatches"]
        md += ["", "%s by fallback and lattice steps per clock (default %d, %d):"
               % (r["module"], r["fallback"], r["steps_per_clock"]), "",
               "| " + " | ".join(sc) + " |", "|" + "---|" * len(sc)]
        md += ["| " + " | ".join("-" if e.get(c) is None else str(e.get(c)) for c in sc) + " |"
               for e in r["steps_sweep"]]
md += ["", "Tools: " + "; ".join(ver.values()) + ". CPU: " + cpu + ".",
       "ice40_lc (placed and routed) includes the out-of-context wrapper's flip-flops (ice40_wrapper_ffs in "
       "summary.json); ice40_lc_module is the module's own, those flip-flops' LCs subtracted."]
open(os.path.join(out, "summary.md"), "w").write("\n".join(md) + "\n")
print("\n".join(md))
PY
# The area/error plot of every module in the summary (docs/HARDWARE.md).
[ "${HW_NO_SYNTH:-0}" = 1 ] || python3 "$root/hw/plot_pareto.py" "$out/summary.json" "$out/pareto.svg" || status=1
exit $status
