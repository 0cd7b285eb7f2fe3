# Shared preamble of the tests/cli/*.sh scripts, sourced by each after it has set `work` (the
# folder the commands' outputs go to):
#     . "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
# It counts passed and failed checks in `pass` and `fail`; a script ends with
#     echo "$pass passed, $fail failed"; [ "$fail" -eq 0 ]
# What a failure shows can be set before sourcing (each script keeps its own):
#     cli_timeout=S         run every `check` command under `timeout S` (default: none)
#     cli_show="tail -20"   the lines of a failed check's stdout and stderr shown (head -20)
#     cli_contains_show=... the lines of the file a failed `contains` shows (head -10)
pass=0; fail=0
cli_timeout=${cli_timeout:-}
cli_show=${cli_show:-head -20}
cli_contains_show=${cli_contains_show:-head -10}

check() {  # check NAME EXPECTED_EXIT COMMAND...   (stdout to $work/out.txt, stderr to err.txt)
    local name=$1 expected=$2; shift 2
    if [ -n "$cli_timeout" ]; then
        timeout "$cli_timeout" "$@" >"$work/out.txt" 2>"$work/err.txt"
    else
        "$@" >"$work/out.txt" 2>"$work/err.txt"
    fi
    local code=$?
    if [ "$code" -eq "$expected" ]; then pass=$((pass + 1)); else
        fail=$((fail + 1)); echo "FAIL: $name: exit $code, expected $expected"
        sed 's/^/    /' "$work/out.txt" "$work/err.txt" | $cli_show
    fi
}
contains() {  # contains NAME FILE PATTERN (extended regex)
    if grep -qE -- "$3" "$2"; then pass=$((pass + 1)); else
        fail=$((fail + 1)); echo "FAIL: $1: '$3' not in $(basename "$2")"; sed 's/^/    /' "$2" | $cli_contains_show
    fi
}
lacks() {  # lacks NAME FILE PATTERN (extended regex)
    if grep -qE -- "$3" "$2"; then fail=$((fail + 1)); echo "FAIL: $1: '$3' in $(basename "$2")"; else pass=$((pass + 1)); fi
}
one_line() {  # one_line NAME FILE: exactly one line
    if [ "$(wc -l < "$2")" -eq 1 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $1: not one line"; cat "$2"; fi
}
json() {  # json FILE EXPR: print a value of a JSON file (j: the file's JSON)
    python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print($2)" "$1"
}
