#!/bin/bash
# Unequal layers (issue "Shadows that hold still", item 4): four slices at equal total texels
# (2048²), the far layer `scale` times the others' side, (3 + scale²) · side² = 2048².
#  1. `forest bench speed-error --sizes 2048 --cascades 4 --far-slice-scale S` for each scale
#     (the grove's 10 scenarios, four methods, the flicker walks);
#  2. `forest truth` at six views of data/scenes/landscape.toml (its walk's clearing, approach and
#     ridge, its flight's start, middle and end; LiSPSM ×4) for each scale.
# Writes OUT/unequal-layers.md and OUT/unequal-layers.json: misclassified pixels summed over the
# scenarios (and per distance band) against equal layers. A run whose report is already in OUT is
# not run again (delete OUT to measure afresh).
#   bash bench/unequal-layers.sh [--out DIR] [--forest BIN] [--scales "0.75 1 1.25 1.5 2"]
set -euo pipefail
OUT=out/unequal-layers
FOREST=build/release/apps/forest
SCALES="0.75 1 1.25 1.5 2"
while [ $# -gt 0 ]; do
	case "$1" in
	--out) OUT=$2; shift 2 ;;
	--forest) FOREST=$2; shift 2 ;;
	--scales) SCALES=$2; shift 2 ;;
	-h | --help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
	*) echo "unequal-layers.sh: unknown argument '$1' (expected --out DIR, --forest BIN, --scales LIST)" >&2; exit 2 ;;
	esac
done
case " $SCALES " in *" 1 "*) ;; *) echo "unequal-layers.sh: --scales must hold 1 (equal layers: the baseline)" >&2; exit 2 ;; esac
[ -x "$FOREST" ] || { echo "unequal-layers.sh: no forest binary at $FOREST (build it, or give --forest)" >&2; exit 2; }
mkdir -p "$OUT/landscape"
side() { python3 -c "print(round(2048 / (3 + $1 * $1) ** 0.5))"; }

for scale in $SCALES; do
	dir="$OUT/speed-error-r$scale"
	[ -f "$dir/report.json" ] && continue
	echo "speed-error, far slice scale $scale ($(side "$scale")² layers)"
	"$FOREST" bench speed-error --sizes 2048 --cascades 4 --far-slice-scale "$scale" --out "$dir" --quiet > /dev/null
done

# name|x y z yaw pitch (eye positions from the paths' frames: 1.7 m over the terrain on the walk,
# 100 m over it in the flight)
VIEWS=("clearing|-219.9 239.2 -108.6 165.8 3" "approach|-270.8 261.4 81.8 163.5 3" "ridge|-285 273.7 135 185 -4"
	"flight-start|1445 339.1 85 45 -15" "flight-middle|1180 311.5 -180 45 -15" "flight-end|915 256.5 -445 35 -15")
for view in "${VIEWS[@]}"; do
	name=${view%%|*}
	for scale in $SCALES; do
		dir="$OUT/landscape/$name-r$scale"
		[ -f "$dir/truth.json" ] && continue
		echo "landscape $name, far slice scale $scale"
		# shellcheck disable=SC2086
		"$FOREST" truth --scene data/scenes/landscape.toml --camera ${view#*|} --cascades 4 --method lispsm \
			--shadow-size "$(side "$scale")" --far-slice-scale "$scale" --out "$dir" > /dev/null
	done
done

cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
python3 - "$OUT" "$SCALES" "$(date -u +%Y-%m-%d) on $(nproc) cores of ${cpu:-an unknown CPU}" <<'EOF'
import json, sys
out, scales, machine = sys.argv[1], sys.argv[2].split(), sys.argv[3]
methods = ["uniform", "uniform-stable", "lispsm", "tsm"]
views = ["clearing", "approach", "ridge", "flight-start", "flight-middle", "flight-end"]

def summed(rows):
    """Misclassified lit-facing pixels over the rows, all and per band (0-50, 50-200, 200+ m)."""
    total, bands = 0.0, [0.0, 0.0, 0.0]
    for r in rows:
        total += r["misclassification"] * r["lit_facing"]
        for i, b in enumerate(r["bands"][:3]):
            bands[i] += b["misclassification"] * b["lit_facing"]
    return total, bands

result = {"machine": machine, "grove": {}, "landscape": {}}
grove = {}
for s in scales:
    report = json.load(open(f"{out}/speed-error-r{s}/report.json"))
    rows = [r for r in report["rows"] if r["blur"] and r["focus"] == "receivers"]
    for r in rows:
        r["lit_facing"] = r["lit_facing_pixels"]
    grove[s] = {m: [r for r in rows if r["method"] == m] for m in methods}
    grove[s]["layers"] = (rows[0]["map_size"], rows[0]["far_map_size"])
    grove[s]["flicker"] = {(f["method"], f["keep_slices"]): f for f in report["flicker"]}
    result["device"] = report["device"]
land = {}
for s in scales:
    rows, layers = [], None
    for v in views:
        t = json.load(open(f"{out}/landscape/{v}-r{s}/truth.json"))
        slices = t["cascades"]["slices"]
        layers = (slices[0]["map_size"], slices[-1]["map_size"])
        rows.append({"misclassification": t["misclassification"]["all"], "lit_facing": t["pixels"]["lit_facing"],
                     "bands": t["bands"], "view": v})
    land[s] = {"rows": rows, "layers": layers}

def ratio(a, b):
    return a / b if b > 0 else float("nan")

lines = [f"Measured {machine}; GL: {result['device']}.", "",
         "By `bash bench/unequal-layers.sh` (1280×720, four slices, 2048² total texels;",
         "the far layer's side `scale` times the others'). Misclassified lit-facing pixels summed over the",
         "views, against equal layers (scale 1); in brackets the same per distance band 0–50 / 50–200 / 200 m+.", "",
         "The grove (`bench speed-error`, data/scenes/forest.toml, its 10 scenarios, blur on, B on the receivers):", "",
         "| far scale | layers | " + " | ".join(methods) + " |", "|---|---|" + "---|" * len(methods)]
for s in scales:
    cells = []
    for m in methods:
        t, b = summed(grove[s][m])
        t0, b0 = summed(grove["1"][m])
        cells.append(f"{ratio(t, t0):.2f}× ({'/'.join(f'{ratio(b[i], b0[i]):.2f}' for i in range(3))})")
        result["grove"].setdefault(s, {})[m] = {"misclassified": ratio(t, t0), "bands": [ratio(b[i], b0[i]) for i in range(3)]}
    near, far = grove[s]["layers"]
    lines.append(f"| {s} | 3×{near}²+{far}² | " + " | ".join(cells) + " |")
lines += ["", "Flicker on the speed-error walk (share of probe states that change), refitted / kept slices:", "",
          "| far scale | uniform | lispsm | tsm | uniform-stable |", "|---|---|---|---|---|"]
for s in scales:
    f = grove[s]["flicker"]
    cell = lambda m: f"{f[(m, False)]['share']:.4f} / {f[(m, True)]['share']:.4f}"
    lines.append(f"| {s} | {cell('uniform')} | {cell('lispsm')} | {cell('tsm')} | {f[('uniform-stable', False)]['share']:.4f} |")
lines += ["", "The landscape (`forest truth`, data/scenes/landscape.toml, LiSPSM ×4, at " + ", ".join(views) + "):", "",
          "| far scale | layers | all views | " + " | ".join(views) + " |", "|---|---|---|" + "---|" * len(views)]
for s in scales:
    t, b = summed(land[s]["rows"])
    t0, b0 = summed(land["1"]["rows"])
    per = [f"{100 * r['misclassification']:.2f}%" for r in land[s]["rows"]]
    result["landscape"][s] = {"misclassified": ratio(t, t0), "bands": [ratio(b[i], b0[i]) for i in range(3)],
                              "views": {r["view"]: r["misclassification"] for r in land[s]["rows"]}}
    near, far = land[s]["layers"]
    lines.append(f"| {s} | 3×{near}²+{far}² | {ratio(t, t0):.2f}× ({'/'.join(f'{ratio(b[i], b0[i]):.2f}' for i in range(3))}) | " + " | ".join(per) + " |")
open(f"{out}/unequal-layers.md", "w").write("\n".join(lines) + "\n")
json.dump(result, open(f"{out}/unequal-layers.json", "w"), indent=1)
print("\n".join(lines))
print(f"\nwrote {out}/unequal-layers.md and unequal-layers.json")
EOF
