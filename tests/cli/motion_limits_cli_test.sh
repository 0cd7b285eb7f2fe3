#!/usr/bin/env bash
# `manta vlm-unsteady` checks a motion's control modes against the aircraft's control limits
# (aero::check_mode_limits; the Ranger 2000's `controls:`, Table 3 of the paper: elevator and
# aileron -25/+15 deg, rudder +-17.5 deg) before the lattice is built: a deflection beyond a limit
# is refused naming the mode, the value, the time and the limits, one far beyond them with the
# degrees-typed-as-radians hint; an elevator of 5 rad is refused by the motion reader already,
# with the same hint. A motion within the limits runs; an AVL geometry file states no limits.
# Usage: motion_limits_cli_test.sh MANTA_BINARY REPO_ROOT WORK_DIR
set -u
manta=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
root=$2
work=$3
rm -rf "$work"; mkdir -p "$work"
cli_timeout=120 cli_show="head -8" cli_contains_show="head -5"
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"  # check, contains, ...; pass, fail
ranger=$root/examples/ranger2000/aircraft.yaml

absent() {  # absent NAME PATH: nothing there
    if [ -e "$2" ]; then fail=$((fail + 1)); echo "FAIL: $1: $2 exists"; else pass=$((pass + 1)); fi
}
motion() {  # motion FILE ELEVATOR AILERON RUDDER: six rows, the deflections in the last one [rad]
    { echo '# v0: 100.0'
      echo 't,x_ref,y_ref,z_ref,phi,theta,psi,mode_elevator,mode_aileron,mode_rudder'
      for i in 0 1 2 3 4; do echo "0.0$i,0,0,0,0,0.02,0,0,0,0"; done
      echo "0.05,0,0,0,0,0.02,0,$2,$3,$4"; } > "$1"
}
# vlm-unsteady on a coarse lattice, a few steps: "${unsteady[@]}" --aircraft A --motion M --out D
unsteady=(vlm-unsteady --dt 0.01 --n-chord 2 --strip-width 0.1)

# An elevator of 5 rad (286 deg typed as radians): the motion reader refuses it.
motion "$work/rad5.csv" 5 0 0
check "elevator 5 rad refused" 2 "$manta" "${unsteady[@]}" --aircraft "$ranger" --motion "$work/rad5.csv" --out "$work/out_rad5"
contains "elevator 5 rad: the column" "$work/err.txt" "column 'mode_elevator' value 5 rad"
contains "elevator 5 rad: unit-slip hint" "$work/err.txt" "degrees typed as radians\? 5 rad would be 286.5 deg"
absent "elevator 5 rad: no output folder" "$work/out_rad5"

# 1.4 rad (80 deg): a deflection, but far beyond the Ranger's elevator: the limits and the hint.
motion "$work/rad14.csv" 1.4 0 0
check "elevator 1.4 rad refused" 2 "$manta" "${unsteady[@]}" --aircraft "$ranger" --motion "$work/rad14.csv" --out "$work/out_rad14"
contains "elevator 1.4 rad: mode, value, time" "$work/err.txt" "rad14.csv: mode 'elevator' = 1.4 rad at t = 0.05 s is outside the aircraft's limits"
contains "elevator 1.4 rad: the limits" "$work/err.txt" "\[-0.4363, 0.2618\] rad \(\[-25.0, 15.0\] deg\)"
contains "elevator 1.4 rad: unit-slip hint" "$work/err.txt" "degrees typed as radians"
contains "elevator 1.4 rad: the aircraft file" "$work/err.txt" "limits from the 'controls' section of .*aircraft.yaml"
absent "elevator 1.4 rad: no output folder" "$work/out_rad14"

# Just beyond each limit (17.2 deg up, 28.6 deg down, 20 deg of rudder): refused naming the
# limit, without the unit-slip hint.
motion "$work/elev.csv" 0.3 0 0
check "elevator 17.2 deg refused" 2 "$manta" "${unsteady[@]}" --aircraft "$ranger" --motion "$work/elev.csv" --out "$work/out_elev"
contains "elevator 17.2 deg: the limit" "$work/err.txt" "mode 'elevator' = 0.3 rad at t = 0.05 s is outside the aircraft's limits \[-0.4363, 0.2618\] rad \(\[-25.0, 15.0\] deg\)"
if grep -q "degrees typed as radians" "$work/err.txt"; then
    fail=$((fail + 1)); echo "FAIL: elevator 17.2 deg: a unit-slip hint for a near miss"
else pass=$((pass + 1)); fi
motion "$work/ail.csv" 0 -0.5 0
check "aileron -28.6 deg refused" 2 "$manta" "${unsteady[@]}" --aircraft "$ranger" --motion "$work/ail.csv" --out "$work/out_ail"
contains "aileron -28.6 deg: the limit" "$work/err.txt" "mode 'aileron' = -0.5 rad .*\(\[-25.0, 15.0\] deg\)"
motion "$work/rud.csv" 0 0 0.35
check "rudder 20 deg refused" 2 "$manta" "${unsteady[@]}" --aircraft "$ranger" --motion "$work/rud.csv" --out "$work/out_rud"
contains "rudder 20 deg: the limit" "$work/err.txt" "mode 'rudder' = 0.35 rad .*\(\[-17.5, 17.5\] deg\)"

# Within the limits (elevator 11.5 deg, aileron -20 deg, rudder 15 deg): it runs.
motion "$work/ok.csv" 0.2 -0.35 0.26
check "within the limits runs" 0 "$manta" "${unsteady[@]}" --aircraft "$ranger" --motion "$work/ok.csv" --out "$work/out_ok"
contains "within the limits: coefficients written" "$work/out_ok/coefficients.csv" "^t,CL,"

# An AVL geometry file (a plate with an elevator flap) states no control limits: 0.3 rad runs.
printf 'Plate\n0.0\n0 0 0.0\n4.0 1.0 4.0\n0.25 0 0\nSURFACE\nWing\n4 1.0 8 1.0\nYDUPLICATE\n0.0\nSECTION\n0 0 0 1 0\nCONTROL\nelevator 1.0 0.75 0 0 0 1.0\nSECTION\n0 2 0 1 0\nCONTROL\nelevator 1.0 0.75 0 0 0 1.0\n' > "$work/plate.avl"
check "AVL file: no limits" 0 "$manta" "${unsteady[@]}" --aircraft "$work/plate.avl" --motion "$work/elev.csv" --out "$work/out_avl"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
