#!/usr/bin/env bash
# End-to-end checks of `manta report` on the fixture run directory tests/data/report/run.
# Usage: report_cli_test.sh MANTA_BINARY REPO_ROOT WORK_DIR. Prints "N passed, N failed".
set -u
manta=$1
root=$2
work=$3
rm -rf "$work"; mkdir -p "$work"
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"  # check, contains, ...; pass, fail
run=$root/tests/data/report/run

exists() {  # exists NAME FILE
    if [ -s "$2" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $1: $2 missing or empty"; fi
}
absent() {  # absent NAME PATH
    if [ ! -e "$2" ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: $1: $2 should not exist"; fi
}

check "report --help" 0 "$manta" report --help
contains "help names --html" "$work/out.txt" "--html"

# The whole run directory.
check "report of a run directory" 0 "$manta" report "$run" --html "$work/report.html"
exists "page written" "$work/report.html"
contains "page is HTML" "$work/report.html" "^<!DOCTYPE html>"
contains "summary line" "$work/out.txt" "run layout"
contains "parts shown" "$work/out.txt" "aircraft, tables, manoeuvre:immelmann, replay:immelmann, provenance"
if grep -qE '(src|href)="(https?:)?//' "$work/report.html"; then
    fail=$((fail + 1)); echo "FAIL: the page refers to an external resource"; else pass=$((pass + 1)); fi

check "report --json" 0 "$manta" report "$run" --html "$work/report2.html" --json
if python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["layout"] == "run" and len(d["parts"]) == 5' "$work/out.txt"; then
    pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: --json output"; head -5 "$work/out.txt"; fi

# Figures: SVG and CSV of every figure; PNG asked of a browser that is not there: a note.
check "report --figures" 0 "$manta" report "$run" --html "$work/r3.html" --figures "$work/fig" --png --chromium "$work/no-such-browser"
for f in manoeuvre-0-histories.svg manoeuvre-0-histories.csv manoeuvre-0-path.svg manoeuvre-0-path.csv \
         replay-0-coefficients.svg replay-0-coefficients.csv replay-0-differences.svg tables-dynamic.svg \
         aircraft-three-view.svg; do
    exists "figure $f" "$work/fig/$f"
done
contains "png note" "$work/out.txt" "no PNG"

# Single output directories.
check "report of an optimise directory" 0 "$manta" report "$run/manoeuvres/immelmann" --html "$work/m.html" --json
contains "optimise layout" "$work/out.txt" '"layout": "optimise"'
check "report of a tables directory" 0 "$manta" report "$run/tables" --html "$work/t.html"
check "report of a replay directory" 0 "$manta" report "$run/replay/immelmann" --html "$work/rp.html"

# Bad input: one line naming file, line and column; the old page is left as it was.
cp -r "$run" "$work/bad"
sed -i '5s/^[^,]*,/oops,/' "$work/bad/replay/immelmann/comparison.csv"
cp "$work/report.html" "$work/keep.html"
check "malformed CSV is bad input" 2 "$manta" report "$work/bad" --html "$work/keep.html"
contains "error names file:line and column" "$work/err.txt" "comparison.csv:5: column 't' value 'oops' is not a number"
if [ "$(wc -l <"$work/err.txt")" -eq 1 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: error is not one line"; cat "$work/err.txt"; fi
if cmp -s "$work/report.html" "$work/keep.html"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: a failed report changed the existing page"; fi
check "malformed JSON is bad input" 2 bash -c "cp -r '$run' '$work/bad2' && printf '{\"a\": 1,\n \"b\": }' > '$work/bad2/run.json' && '$manta' report '$work/bad2' --html '$work/bad2.html'"
contains "JSON error names line and column" "$work/err.txt" "run.json:2:[0-9]+: invalid JSON"
absent "no page after a failure" "$work/bad2.html"
check "not a directory" 2 "$manta" report "$work/nowhere" --html "$work/x.html"
contains "not a directory message" "$work/err.txt" "not a directory"
mkdir -p "$work/empty"
check "nothing to report" 2 "$manta" report "$work/empty" --html "$work/x.html"
absent "no page for nothing" "$work/x.html"
check "missing --html" 2 "$manta" report "$run"

# A second table set beside the tables (--compare-tables): the fixture's with CL scaled by 1.1.
cmp=$work/scaled
cp -r "$run/tables" "$cmp"
awk -F, -v OFS=, -v CONVFMT=%.17g '/^#/ || $1 == "table" { print; next } { $6 = $6 * 1.1; print }' \
    "$run/tables/tables.csv" > "$cmp/tables.csv"
sed -i 's/"name": "vlm"/"name": "scaled"/' "$cmp/summary.json"
check "report --compare-tables" 0 "$manta" report "$run" --html "$work/cmp.html" --compare-tables "$cmp" --json
if python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
c = d["comparison"]
assert "compare-tables" in d["parts"], d["parts"]
assert c["main"]["label"] == "vlm" and c["compare"]["label"] == "scaled", c["main"]
assert len(c["summary"]) == 2
for e in c["summary"]:
    assert abs(e["ratio"]["CL_alpha"] - 1.1) < 1e-9 and abs(e["ratio"]["CL_0"] - 1.1) < 1e-9, e
    assert abs(e["ratio"]["Cm_alpha"] - 1) < 1e-12 and e["main"]["CL_alpha"] > 3, e
    assert e["fit_alpha_deg"] == [-2, 0, 2, 4], e
el = [x for x in c["controls"] if x["control"] == "elevator"][0]
assert abs(el["ratio"]["dCL_delevator"] - 1.1) < 1e-9 and el["main"]["dCm_delevator"] < 0, el
assert c["slices"]["exact"] == 4
' "$work/out.txt"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: --compare-tables --json"; head -c 600 "$work/out.txt"; fi
contains "comparison summary in the page" "$work/cmp.html" 'id="compare-summary"'
contains "comparison data in the page" "$work/cmp.html" '"name":"scaled samples"'
check "compare a tables directory, labelled, with figures" 0 "$manta" report "$run/tables" --html "$work/cmp2.html" \
    --compare-tables "$cmp/" --compare-label "VLM x1.1" --figures "$work/cmpfig"
contains "summary lines" "$work/out.txt" "compared with VLM x1.1 .*vlm / VLM x1.1 \(ratio\)"
contains "summary line per Mach" "$work/out.txt" "M 0.2: CL_alpha [0-9.]+ / [0-9.]+ \(1.1\)"
for f in tables-compare-summary.svg tables-compare-summary.csv tables-static-M0-b0.svg tables-static-M1-b0.csv \
         tables-elevator-M1.svg tables-dynamic-compare-M0.svg tables-dynamic-compare-M1.csv; do
    exists "comparison figure $f" "$work/cmpfig/$f"
done
contains "both tables in a static slice's CSV" "$work/cmpfig/tables-static-M0-b0.csv" "^0,VLM x1.1,"
contains "the main table too" "$work/cmpfig/tables-static-M0-b0.csv" "^0,vlm,"

# Bad second tables: one line, exit 2, the old page left as it was.
cp "$work/cmp.html" "$work/keep2.html"
check "compare with a run directory" 2 "$manta" report "$run" --html "$work/cmp.html" --compare-tables "$run"
contains "not a tables directory" "$work/err.txt" "no tables.csv; --compare-tables expects a .manta tables --out. directory \(such as"
if [ "$(wc -l <"$work/err.txt")" -eq 1 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: error is not one line"; cat "$work/err.txt"; fi
if cmp -s "$work/cmp.html" "$work/keep2.html"; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: a failed comparison changed the page"; fi
check "compare with nothing" 2 "$manta" report "$run" --html "$work/x.html" --compare-tables "$work/nowhere"
contains "compare dir not a directory" "$work/err.txt" "nowhere: not a directory"
mkdir -p "$work/cx"
cp "$cmp"/* "$work/cx/"
awk -F, -v OFS=, '/^#/ { print; next } $1 == "table" { print $0, "CX"; next } { print $0, 0 }' "$cmp/tables.csv" > "$work/cx/tables.csv"
check "mismatched coefficient sets" 2 "$manta" report "$run" --html "$work/x.html" --compare-tables "$work/cx"
contains "coefficients named" "$work/err.txt" "coefficient columns CL,CD,CY,Cl,Cm,Cn,CX differ from those of .*tables.csv \(CL,CD,CY,Cl,Cm,Cn\)"
if [ "$(wc -l <"$work/err.txt")" -eq 1 ]; then pass=$((pass + 1)); else fail=$((fail + 1)); echo "FAIL: error is not one line"; cat "$work/err.txt"; fi
check "nothing to compare with" 2 "$manta" report "$run/replay/immelmann" --html "$work/x.html" --compare-tables "$cmp"
contains "no static table message" "$work/err.txt" "has no static table to compare with"
absent "no page after failed comparisons" "$work/x.html"
check "--compare-label needs --compare-tables" 2 "$manta" report "$run" --html "$work/x.html" --compare-label x

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
