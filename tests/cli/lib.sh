# Shared by the CLI test scripts (sourced; not a test itself): a temporary
# folder removed on exit, pass/fail counters and the expect helper.
#   . "$(dirname "$0")/lib.sh"   after setting persp="$1"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok()   { pass=$((pass + 1)); }
bad()  { fail=$((fail + 1)); echo "FAIL: $*"; }

# expect CODE PATTERN -- command...: exit code and a stderr/stdout pattern
expect() {
    local code="$1" pattern="$2"; shift 3
    local out rc
    out=$("$@" 2>&1); rc=$?
    if [ "$rc" -ne "$code" ]; then bad "$* exited $rc, expected $code: $out"; return; fi
    if ! grep -qE -- "$pattern" <<<"$out"; then bad "$* output lacks /$pattern/: $out"; return; fi
    ok
}
