#!/bin/bash
# This engine against the classic CHC + LiSPSM forest demo (GPU Gems 2 ch. 6, "demo1"; the port in
# ../shared/peer/gg2-demo1), side by side on this machine: the two programs take turns, in pairs,
# so that drift of the machine hits both alike. Each pair runs the classic demo's walk (CHC,
# shadows on, 2048² map) and then `forest walkthrough` on data/scenes/thesis-demo.toml along
# data/paths/thesis-walk.toml (chc++, LiSPSM 2048², blur off) at the same size, tree grid, warm-up
# and frame count. It prints each run's mean and p95 frame time and triangles, the ratio
# forest / classic per pair and the median of the pairs, and writes them as JSON and as a Markdown
# table stamped with the machine and date (DIR/thesis-demo.md, or FILE with --markdown; the README's
# table: --markdown docs/benchmarks/thesis-demo.md). The runs' logs and reports stay in DIR.
#
# usage: bench/peer-thesis-demo.sh [--pairs N] [--trees "5000 10000"] [--size 800x600]
#                                  [--warmup 30] [--frames 200] [--timing queries] [--out DIR]
#                                  [--markdown FILE]
#   --trees: the classic demo's request; it places a square grid (5000 → 72² = 5184, 10000 → 101² =
#            10201 trees) and the forest scene gets the grid it placed.
#   --timing: the engine's pass timing, queries (timer queries; nothing in a frame waits, as in the
#            classic demo) or profile (each pass closed by glFinish: the pipeline serialised)
# env: FOREST_BIN  the forest program (default build/release/apps/forest)
#      GG2_BIN     the classic demo (default /tmp/gg2-demo1-build/src/CHC/chc)
#      GG2_DIR     the port's scripts (default ../shared/peer/gg2-demo1 next to this repository)
# Exit status 77 (skipped) when the classic demo is not built or cannot run: the message says how
# to build it.
#
# Frame times: the classic demo's from the start of display() to after the swap and glFinish; the
# engine's its frame interval (report.json interval_ms: from a frame's start to the next one's, so
# all of its GPU work is in it). Both render with Mesa llvmpipe here; the classic demo under Xvfb
# (GLX), the engine headless (EGL).
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
FOREST_BIN=${FOREST_BIN:-$REPO/build/release/apps/forest}
GG2_BIN=${GG2_BIN:-/tmp/gg2-demo1-build/src/CHC/chc}
GG2_DIR=${GG2_DIR:-$REPO/../shared/peer/gg2-demo1}
PAIRS=3
TREES="5000 10000"
SIZE=800x600
WARMUP=30
FRAMES=200
TIMING=queries
OUT=out/peer-thesis-demo
MARKDOWN=

usage() { sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
	case "$1" in
		--pairs) PAIRS=$2; shift 2 ;;
		--trees) TREES=$2; shift 2 ;;
		--size) SIZE=$2; shift 2 ;;
		--warmup) WARMUP=$2; shift 2 ;;
		--frames) FRAMES=$2; shift 2 ;;
		--timing) TIMING=$2; shift 2 ;;
		--out) OUT=$2; shift 2 ;;
		--markdown) MARKDOWN=$2; shift 2 ;;
		-h|--help) usage; exit 0 ;;
		*) echo "peer-thesis-demo: error: unknown option '$1'; see --help" >&2; exit 2 ;;
	esac
done
for n in "$PAIRS" "$WARMUP" "$FRAMES"; do
	[[ "$n" =~ ^[0-9]+$ ]] || { echo "peer-thesis-demo: error: '$n': expected a whole number" >&2; exit 2; }
done
[ "$PAIRS" -ge 1 ] && [ "$FRAMES" -ge 1 ] || { echo "peer-thesis-demo: error: --pairs and --frames must be at least 1" >&2; exit 2; }
[ "$TIMING" = queries ] || [ "$TIMING" = profile ] || { echo "peer-thesis-demo: error: --timing '$TIMING': expected queries or profile" >&2; exit 2; }
[[ "$SIZE" =~ ^([0-9]+)x([0-9]+)$ ]] || { echo "peer-thesis-demo: error: --size '$SIZE': expected WxH, e.g. 800x600" >&2; exit 2; }
WIDTH=${BASH_REMATCH[1]}
HEIGHT=${BASH_REMATCH[2]}

skip() {
	echo "SKIP peer-thesis-demo: $1" >&2
	exit 77
}
[ -x "$FOREST_BIN" ] || { echo "peer-thesis-demo: error: no forest program at $FOREST_BIN (build it: cmake --preset release && cmake --build --preset release)" >&2; exit 2; }
[ -f "$GG2_DIR/run-bench.sh" ] || skip "no classic demo port at $GG2_DIR (set GG2_DIR)"
[ -x "$GG2_BIN" ] || skip "the classic demo is not built at $GG2_BIN: see $GG2_DIR/README.md (fetch github:QianMo/GPU-Gems-Book-Source-Code with the fetch tool, then $GG2_DIR/fetch-and-build.sh GIT_DIR)"
command -v xvfb-run >/dev/null || skip "xvfb-run is missing (apt-get install -y xvfb xauth)"

mkdir -p "$OUT"
RESULTS="$OUT/runs.jsonl"
: > "$RESULTS"
SCENE_DIR=$(mktemp -d)
trap 'rm -rf "$SCENE_DIR"' EXIT

for request in $TREES; do
	[[ "$request" =~ ^[0-9]+$ ]] && [ "$request" -ge 1 ] || { echo "peer-thesis-demo: error: --trees '$request': expected whole numbers ≥ 1" >&2; exit 2; }
	for pair in $(seq 1 "$PAIRS"); do
		echo "== $request trees requested, pair $pair of $PAIRS: classic demo" >&2
		peer_log="$OUT/classic-$request-$pair.txt"
		if ! GG2_BIN="$GG2_BIN" bash "$GG2_DIR/run-bench.sh" --modes 2 --shadows 1 --path walk --smsize 2048 --trees "$request" \
			--size "$SIZE" --warmup "$WARMUP" --frames "$FRAMES" > "$peer_log" 2>&1; then
			cat "$peer_log" >&2
			skip "the classic demo did not run (its output is above)"
		fi
		# The grid the classic demo placed (its INFO line: trees=G²); the forest scene gets the same.
		placed=$(sed -n 's/^INFO .* trees=\([0-9]*\) .*/\1/p' "$peer_log" | head -1)
		grid=$(python3 -c "import math; print(math.isqrt(${placed:-0}))")
		[ "$grid" -ge 1 ] && [ $((grid * grid)) -eq "${placed:-0}" ] ||
			{ echo "peer-thesis-demo: error: no square tree count in the classic demo's INFO line ($peer_log)" >&2; exit 1; }
		scene="$SCENE_DIR/thesis-demo-$grid.toml"
		sed "s/^grid = [0-9]*/grid = $grid/" "$REPO/data/scenes/thesis-demo.toml" > "$scene"
		grep -q "^grid = $grid\b" "$scene" || { echo "peer-thesis-demo: error: data/scenes/thesis-demo.toml has no 'grid = ' line to set" >&2; exit 2; }
		echo "== $((grid * grid)) trees, pair $pair of $PAIRS: forest walkthrough" >&2
		"$FOREST_BIN" walkthrough --scene "$scene" --path "$REPO/data/paths/thesis-walk.toml" --width "$WIDTH" --height "$HEIGHT" \
			--warmup "$WARMUP" --frames $((WARMUP + FRAMES)) --blur 0 --every 1000000 --timing "$TIMING" --quiet \
			--out "$OUT/forest-$grid-$pair" > "$OUT/forest-$grid-$pair.txt" 2>&1 ||
			{ cat "$OUT/forest-$grid-$pair.txt" >&2; echo "peer-thesis-demo: error: forest walkthrough failed" >&2; exit 1; }
		python3 - "$peer_log" "$OUT/forest-$grid-$pair/report.json" "$((grid * grid))" "$pair" >> "$RESULTS" <<'EOF'
import json, re, sys
peer_log, report, trees, pair = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
fields = None
for line in open(peer_log):
    if line.startswith("RESULT "):
        fields = dict(kv.split("=", 1) for kv in line.split()[1:] if "=" in kv)
if fields is None:
    sys.exit(f"peer-thesis-demo: no RESULT line in {peer_log}")
forest = json.load(open(report))
summary = forest["summary"]
print(json.dumps({
    "trees": trees, "pair": pair,
    "classic": {"ms_mean": float(fields["ms_mean"]), "ms_p95": float(fields["p95"]), "shadow_ms_mean": float(fields["shadow_ms_mean"]),
                "eye_triangles": float(fields["eye_tris"]), "shadow_triangles": float(fields["shadow_tris"]),
                "queries": float(fields["queries"])},
    "forest": {"ms_mean": summary["interval_ms"]["mean"], "ms_p95": summary["interval_ms"]["p95"],
               "issue_ms_mean": summary["frame_ms"]["mean"], "timing": forest["settings"]["timing"],
               "passes_ms": {k: v["mean"] for k, v in summary["passes_ms"].items()},
               "eye_triangles": summary["triangles_geometry"]["mean"], "shadow_triangles": summary["triangles_shadow"]["mean"],
               "queries": summary["queries"]["mean"]},
}))
EOF
	done
done

MACHINE="$(nproc) cores of $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -1)"
python3 - "$RESULTS" "$OUT/peer-thesis-demo.json" "$SIZE" "${MARKDOWN:-$OUT/thesis-demo.md}" "$MACHINE" <<'EOF'
import datetime, json, statistics, sys
runs = [json.loads(line) for line in open(sys.argv[1])]
size = sys.argv[3]
markdown = [f"# The thesis demo scene against the classic demo\n",
            f"Measured {datetime.date.today().isoformat()} on {sys.argv[5]} (Mesa llvmpipe) by `bash bench/peer-thesis-demo.sh`: "
            f"the classic CHC + LiSPSM demo (GPU Gems 2 ch. 6; CHC, 2048²) and `forest walkthrough` (chc++, LiSPSM 2048², blur off, "
            f"--timing {runs[0]['forest']['timing']}) on data/scenes/thesis-demo.toml along data/paths/thesis-walk.toml, {size}, taking "
            "turns in pairs. Frame: the classic demo's display() to after swap + glFinish; the engine's frame interval (start to next start).\n",
            "| trees | pair | classic mean ms | p95 | eye / shadow triangles | forest mean ms | p95 | eye / shadow triangles | forest / classic |",
            "|---|---|---|---|---|---|---|---|---|"]
summary = {"size": size, "runs": runs, "median_ratio": {}}
passLines = []
print(f"\nforest walkthrough (chc++, lispsm 2048², blur off, --timing {runs[0]['forest']['timing']}) against the classic CHC + LiSPSM demo (CHC, 2048²), {size}, one machine, alternating runs")
print("frame: the classic demo's display() to after swap + glFinish; the engine's frame interval (start to next start)")
print(f"{'trees':>6} {'pair':>4} | {'classic mean':>12} {'p95':>7} {'eye tris':>9} {'shadow tris':>11} | {'forest mean':>11} {'p95':>7} {'eye tris':>9} {'shadow tris':>11} | {'forest/classic':>14}")
for trees in sorted({r["trees"] for r in runs}):
    ratios = []
    for r in (r for r in runs if r["trees"] == trees):
        c, f = r["classic"], r["forest"]
        ratio = f["ms_mean"] / c["ms_mean"]
        ratios.append(ratio)
        print(f"{trees:>6} {r['pair']:>4} | {c['ms_mean']:>9.1f} ms {c['ms_p95']:>7.1f} {c['eye_triangles']:>9.0f} {c['shadow_triangles']:>11.0f} | "
              f"{f['ms_mean']:>8.1f} ms {f['ms_p95']:>7.1f} {f['eye_triangles']:>9.0f} {f['shadow_triangles']:>11.0f} | {ratio:>14.3f}")
        markdown.append(f"| {trees} | {r['pair']} | {c['ms_mean']:.1f} | {c['ms_p95']:.1f} | {c['eye_triangles']:.0f} / {c['shadow_triangles']:.0f} | "
                        f"{f['ms_mean']:.1f} | {f['ms_p95']:.1f} | {f['eye_triangles']:.0f} / {f['shadow_triangles']:.0f} | {ratio:.3f} |")
    median = statistics.median(ratios)
    summary["median_ratio"][str(trees)] = median
    print(f"{trees:>6} median of {len(ratios)} pairs: forest / classic mean frame = {median:.3f}")
    markdown.append(f"| {trees} | median of {len(ratios)} | | | | | | | **{median:.3f}** |")
    passes = {k: statistics.mean(r["forest"]["passes_ms"][k] for r in runs if r["trees"] == trees) for k in runs[0]["forest"]["passes_ms"]}
    passLine = ("forest passes (ms, mean of the pairs): " + ", ".join(f"{k} {v:.1f}" for k, v in passes.items() if v > 0) +
                f"; classic shadow pass {statistics.mean(r['classic']['shadow_ms_mean'] for r in runs if r['trees'] == trees):.1f} ms")
    print("       " + passLine)
    passLines.append(f"- {trees} trees: {passLine}")
json.dump(summary, open(sys.argv[2], "w"), indent=1)
open(sys.argv[4], "w").write("\n".join(markdown) + "\n\n" + "\n".join(passLines) + "\n")
print(f"wrote {sys.argv[2]} and {sys.argv[4]}")
EOF
