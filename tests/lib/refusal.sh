# Sourced by the script tests: how they fail, and how they check a refusal of bad input.

fail() { echo "FAIL: $*" >&2; exit 1; }

# expect_refusal [--prefix|--exact] PATTERN COMMAND...
# COMMAND must exit with status 2 within REFUSAL_TIMEOUT seconds (default 60), writing exactly one
# line, "rayfarm: error: ..." that contains PATTERN (--prefix: the text after "rayfarm: error: "
# starts with PATTERN; --exact: it is PATTERN).
expect_refusal() {
    local how=contains pattern err status
    case "$1" in --prefix) how=prefix; shift ;; --exact) how=exact; shift ;; esac
    pattern=$1
    shift
    set +e
    err=$(timeout "${REFUSAL_TIMEOUT:-60}" "$@" 2>&1 >/dev/null)
    status=$?
    set -e
    [ "$status" -eq 2 ] || fail "$*: exit status $status, expected 2 ($err)"
    [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "$*: expected one error line, got: $err"
    case "$how" in
    contains) case "$err" in "rayfarm: error: "*"$pattern"*) return 0 ;; esac ;;
    prefix) case "$err" in "rayfarm: error: $pattern"*) return 0 ;; esac ;;
    exact) [ "$err" = "rayfarm: error: $pattern" ] && return 0 ;;
    esac
    fail "$*: unexpected message: $err"
}
