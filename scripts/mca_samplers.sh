#!/usr/bin/env bash
# Static throughput model of the span samplers of src/texture/fastspan.c
# with llvm-mca, for CPUs we cannot run on.
#
# fastspan.c compiles one inline body per filter (fastspan_body.h) three
# times (baseline SSE2, AVX2 = 8 lanes, AVX-512 = 16 lanes), and
# fastspan_gather.c the AVX2 and AVX-512 ones again with
# -mtune-ctrl=use_gather; a variant is picked at run time (PERSP_SIMD_AUTO
# times the two fetches). The "gather" variant below models the latter.
# This script compiles the file as the build does, finds the hot
# per-vector loops of the chosen functions (wrap repeat/repeat, the corridor
# benchmark's state) by name, classifies each into its stage (lambda, mip
# levels, tap addresses, texel fetch and weighting, blend of two levels,
# packing, scalar copy), runs llvm-mca on every stage for every CPU model,
# and prints cycles per iteration, pixels per iteration, cycles per pixel and
# the busiest resource, with the sum over the stages of one function.
#
#   scripts/mca_samplers.sh [WORKDIR]          (default: a new temporary folder)
#
# WORKDIR keeps the assembly (fastspan.VARIANT.s, reused when present: delete
# it after changing the sources) and one llvm-mca input per block.
#
# Environment:
#   CC=gcc  LLVM_MCA=llvm-mca  ITER=100
#   CPUS="skylake-avx512 cascadelake icelake-server znver3"
#   FUNCS="nearest_avx2_RR nearest_avx512_RR bilinear_avx2_RR ..." (the AVX2
#   variants fetch and weigh the linear filters in linear_sum_avx2, a
#   function of its own: its row adds to theirs)
#   VARIANTS="asis gather"   asis: the flags of the build;
#                            gather: the same plus -mtune-ctrl=use_gather, so
#                            that GCC fetches texels with vpgatherdd (what the
#                            samplers would look like with hardware gathers)
#
# What the numbers are: llvm-mca's steady-state throughput of one loop body
# in isolation (all loads hit L1, no branch mispredictions, no frequency
# changes, no span set-up, no remainder loops). Sum of the stages = cycles
# per pixel of a full span. Scheduling models without AVX-512 (znver3, the
# newest AMD model of LLVM 14) cannot run 512-bit blocks; those rows say n/a.
# Needs: gcc (or a CC accepting GCC's target attributes), llvm-mca, python3.
set -eu

root="$(cd "$(dirname "$0")/.." && pwd)"
work="${1:-$(mktemp -d)}"
mkdir -p "$work"
cc="${CC:-gcc}"
mca="${LLVM_MCA:-llvm-mca}"
iter="${ITER:-100}"
cpus="${CPUS:-skylake-avx512 cascadelake icelake-server znver3}"
funcs="${FUNCS:-nearest_avx2_RR nearest_avx512_RR bilinear_avx2_RR linear_sum_avx2 bilinear_avx512_RR trilinear_avx2_RR trilinear_avx512_RR}"
variants="${VARIANTS:-asis gather}"

# The flags of the library's objects (CMakeLists.txt: CMAKE_C_STANDARD 11,
# PERSP_CFLAGS, the Release -O3 -DNDEBUG, position-independent, hidden);
# warnings and debug information do not change the code.
flags=(-O3 -g0 -DNDEBUG -fPIC -fvisibility=hidden -ffp-contract=off -fno-math-errno
       -fno-trapping-math -D_POSIX_C_SOURCE=200809L -std=c11
       -I"$root/include" -I"$root/src")

echo "work folder: $work" >&2
for v in $variants; do
    case "$v" in
        asis) extra=() ;;
        gather) extra=(-mtune-ctrl=use_gather) ;;
        *) echo "unknown variant $v" >&2; exit 2 ;;
    esac
    if [ ! -s "$work/fastspan.$v.s" ]; then
        echo "compiling fastspan.c ($v)" >&2
        "$cc" "${flags[@]}" ${extra[@]+"${extra[@]}"} -S -o "$work/fastspan.$v.s" "$root/src/texture/fastspan.c"
    fi
done

python3 - "$work" "$mca" "$iter" "$cpus" "$funcs" "$variants" <<'EOF'
import os, re, subprocess, sys

work, mca, iters = sys.argv[1], sys.argv[2], int(sys.argv[3])
cpus, funcs, variants = sys.argv[4].split(), sys.argv[5].split(), sys.argv[6].split()


def function_lines(asm, name):
    """The lines of one function, from its label to its .size directive."""
    start = asm.index(name + ':')
    for i in range(start, len(asm)):
        t = asm[i].split()
        if len(t) > 1 and t[0] == '.size' and t[1].rstrip(',') == name:
            return asm[start:i]
    raise SystemExit('no end of ' + name)


def segments(body):
    """Straight-line runs of instructions: a label starts one, a jump ends
    one. Each is (label or None, [instructions], jump target or None)."""
    out, label, ins = [], None, []
    for line in body:
        m = re.match(r'^(\.?\w+):', line)
        if m:
            if ins:
                out.append((label, ins, None))
            label, ins = m.group(1), []
            continue
        if not line.startswith('\t') or line.strip().startswith('.'):
            continue
        ins.append(line.rstrip())
        op = line.split()
        if op[0].startswith('j'):
            out.append((label, ins, op[1] if len(op) > 1 else None))
            label, ins = None, []
    if ins:
        out.append((label, ins, None))
    return out


def ops(ins):
    return [l.split()[0] for l in ins]


def lanes(ins):
    text = '\n'.join(ins)
    if '%zmm' in text:
        return 16
    if '%ymm' in text:
        return 8
    if re.search(r'\tv?\w+ps\t|\tvp\w+d\t', text):
        return 4
    return 1


def stage(ins, is_loop):
    """Which stage of the sampler a block is, or None for set-up and
    remainder code. The signatures follow the stages of fastspan.c."""
    o = set(ops(ins))
    text = '\n'.join(ins)
    vec = lanes(ins) > 1
    floor = bool(o & {'vroundps', 'vrndscaleps'})
    if not vec:
        # nearest's copy loop dst[k] = tex[addr[k]] stays scalar
        if is_loop and len(ins) <= 8 and re.search(r'\tmovl\t\(%\w+,%\w+,4\), %\w+', text):
            return 'copy'
        return None
    if 'vdivps' in o:
        return 'lambda'
    if 'vcvtdq2ps' in o and ({'vpinsrd', 'vpgatherdd'} & o) and ops(ins).count('vmulps') >= 8:
        return 'fetch'
    if re.search(r'vpslld\t\$24', text) and 'vcvttps2dq' in o:
        return 'pack'
    if floor and 'vcvttps2dq' in o and 'vmulps' in o:
        return 'taps'
    if floor and 'vcvttps2dq' in o:
        return 'levels'
    if (not is_loop and len(ins) <= 8 and {'vsubps', 'vmulps', 'vaddps'} <= o
            and 'vcvttps2dq' not in o):
        return 'blend'
    return None


# The stages each filter runs per span, and how often (fastspan.c):
# trilinear computes taps and fetches for two levels, and blends four
# channels. A stage found fewer times than this as a loop was unrolled by
# GCC; the stage's loop, or else its straight-line copy, stands in for it.
STAGES = {
    'nearest': [('taps', 1), ('copy', 1)],
    'bilinear': [('taps', 1), ('fetch', 1), ('pack', 1)],
    'trilinear': [('lambda', 1), ('levels', 1), ('taps', 2), ('fetch', 2), ('blend', 4),
                  ('pack', 1)],
}


def blocks(asm, name):
    """The blocks that run per pixel, as (stage, instructions, count): the
    innermost loops of each stage in order of appearance, and where GCC
    unrolled a stage completely, the shortest straight-line copy at the
    widest vector width of that stage (narrower copies are remainders)."""
    loops, straight = {}, {}
    for label, ins, target in segments(function_lines(asm, name)):
        is_loop = label is not None and target == label
        st = stage(ins, is_loop)
        if st is not None:
            (loops if is_loop else straight).setdefault(st, []).append(ins)
    out = []
    for st, count in STAGES[name.split('_')[0]]:
        got = loops.get(st, [])
        if st == 'blend':  # one block per channel, never a loop of its own
            got = []
        picked = got[:count]
        if got and len(picked) < count:
            # the same stage once more (trilinear's second level): where GCC
            # unrolled that copy, its loop form models the same work better
            picked += [got[-1]] * (count - len(picked))
        if len(picked) < count and straight.get(st):
            c = straight[st]
            w = max(lanes(x) for x in c)
            fill = min((x for x in c if lanes(x) == w), key=len)
            picked += [fill] * (count - len(picked))
        if len(picked) < count:
            print('warning: %s: stage %s found %d times, expected %d'
                  % (name, st, len(picked), count), file=sys.stderr)
        if st == 'blend' and picked:
            out.append((st, picked[0], count))
        else:
            out += [(st, ins, 1) for ins in picked]
    return out


def run_mca(cpu, path):
    r = subprocess.run([mca, '-mcpu=' + cpu, '-iterations=%d' % iters, '-instruction-info=0',
                        path], capture_output=True, text=True)
    if r.returncode != 0:
        return None
    out = r.stdout
    cycles = int(re.search(r'Total Cycles:\s+(\d+)', out).group(1))
    uops = int(re.search(r'Total uOps:\s+(\d+)', out).group(1))
    width = int(re.search(r'Dispatch Width:\s+(\d+)', out).group(1))
    rthr = float(re.search(r'Block RThroughput:\s+([\d.]+)', out).group(1))
    names = dict(re.findall(r'^\[([\d.]+)\]\s+-\s+(\S+)', out, re.M))
    m = re.search(r'Resource pressure per iteration:\n(.*)\n(.*)\n', out)
    cols, vals = m.group(1).split(), m.group(2).split()
    press = {}
    for c, v in zip(cols, vals):
        n = names.get(c.strip('[]'), c)
        n = re.sub(r'^(SKX|ICX|Zn3)', '', n)
        if v != '-':
            press[n] = max(press.get(n, 0.0), float(v))
    top = sorted(press.items(), key=lambda kv: -kv[1])[:2]
    per = cycles / iters
    why = ', '.join('%s %.1f' % kv for kv in top)
    if uops / iters / width >= 0.9 * per:
        why = 'dispatch %d uops; ' % (uops // iters) + why
    return per, rthr, why


asmcache = {}
rows = []
for v in variants:
    asm = open(os.path.join(work, 'fastspan.%s.s' % v)).read().split('\n')
    for f in funcs:
        bl = blocks(asm, f)
        paths = []
        for i, (st, ins, count) in enumerate(bl):
            p = os.path.join(work, '%s.%s.%d.%s.s' % (v, f, i, st))
            with open(p, 'w') as fh:
                fh.write('# LLVM-MCA-BEGIN %s\n%s\n# LLVM-MCA-END\n' % (st, '\n'.join(ins)))
            paths.append(p)
        for cpu in cpus:
            total, ok = 0.0, True
            for (st, ins, count), p in zip(bl, paths):
                r = run_mca(cpu, p)
                ln = lanes(ins)
                if r is None:
                    ok = False
                    rows.append((f, v, cpu, st, None, ln, None, 'n/a: not in this model'))
                    continue
                per, rthr, why = r
                if cpu.startswith('znver') and 'vpgather' in '\n'.join(ins):
                    # LLVM 14's Zen models cost a gather as one simple uop;
                    # real Zen 2-4 gathers are microcoded and far slower.
                    why = 'gather mis-modelled (1 uop); ' + why
                cpp = per * count / ln
                total += cpp
                rows.append((f, v, cpu, st + ('x%d' % count if count > 1 else ''), per, ln, cpp, why))
            rows.append((f, v, cpu, 'TOTAL', None, None, total if ok else None, ''))

print('| function | variant | cpu | stage | cycles/iter | px/iter | cycles/px | busiest resources (cycles/iter) |')
print('|---|---|---|---|---:|---:|---:|---|')
for f, v, cpu, st, per, ln, cpp, why in rows:
    fmt = lambda x, p: '-' if x is None else ('%.' + str(p) + 'f') % x
    if st == 'TOTAL':
        print('| **%s** | %s | %s | **total** | | | **%s** | |' % (f, v, cpu, fmt(cpp, 2)))
    else:
        print('| %s | %s | %s | %s | %s | %s | %s | %s |' % (f, v, cpu, st, fmt(per, 1), ln or '-', fmt(cpp, 2), why))
# Summary: cycles per pixel of each function (all stages), one column per CPU.
print()
print('| function | variant | ' + ' | '.join(cpus) + ' |')
print('|---|---|' + '---:|' * len(cpus))
tot = {(f, v, cpu): cpp for f, v, cpu, st, per, ln, cpp, why in rows if st == 'TOTAL'}
for v in variants:
    for f in funcs:
        cells = [tot.get((f, v, c)) for c in cpus]
        print('| %s | %s | ' % (f, v) + ' | '.join('n/a' if x is None else '%.2f' % x for x in cells) + ' |')
EOF
