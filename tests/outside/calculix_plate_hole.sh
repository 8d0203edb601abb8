#!/usr/bin/env bash
# Runs CalculiX (ccx, e.g. Debian's calculix-ccx) on freemesh's deck of the
# plate with a hole, order 1 and 2: the outer loop held, a pressure of 100
# on the hole's surface. Prints each run's end and the radial displacement
# of the hole's nodes (positive: the hole opens, as it must).
#   tests/outside/calculix_plate_hole.sh [path/to/freemesh]
set -euo pipefail
freemesh=${1:-target/release/freemesh}
domain=$(cd "$(dirname "$0")/.." && pwd)/inputs/plate-hole.json
dir=$(mktemp -d)
cd "$dir"
for order in 1 2; do
    "$freemesh" mesh "$domain" --order "$order" -o "ph$order.inp"
    cat "ph$order.inp" - > "job$order.inp" <<'END'
*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL
1.
*STEP
*STATIC
*BOUNDARY
outer, 1, 2
*DSLOAD
hole_1_S, P, 100.
*NODE PRINT, NSET=hole_1
U
*END STEP
END
    ccx -i "job$order" > "ccx$order.log" 2>&1 && echo "order $order: ccx exit 0" || { echo "order $order: ccx failed"; tail "ccx$order.log"; exit 1; }
    python3 - "job$order" <<'END'
import math, sys
job = sys.argv[1]
nodes, sec = {}, False
for line in open(job + ".inp"):
    if line.startswith("*NODE, NSET=NALL"):
        sec = True
        continue
    if line.startswith("*"):
        sec = False
    if sec:
        i, x, y = line.split(",")
        nodes[int(i)] = (float(x), float(y))
radial = []
for line in open(job + ".dat"):
    p = line.split()
    if len(p) == 4 and p[0].isdigit():
        x, y = nodes[int(p[0])]
        r = math.hypot(x - 3, y - 2)
        radial.append(((x - 3) * float(p[1]) + (y - 2) * float(p[2])) / r)
print(f"  {len(radial)} hole nodes, radial displacement {min(radial):.4e} .. {max(radial):.4e}")
END
done
