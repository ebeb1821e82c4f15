#!/usr/bin/env bash
# Counts the GL calls one steady-state frame of `forest walkthrough` makes (DESIGN §9), with
# apitrace: the walk is traced twice, A and B frames long, and per frame = (calls in B − calls in A)
# / (B − A), so setup and teardown cancel out (the walk without its video, whose read-back is output). Prints every call's count per frame and the figures
# that stall a GPU or cost a lookup: glFinish, glGetUniformLocation, loose uniform sets
# (gl[Program]Uniform*: per-frame values belong in uniform blocks), GL_QUERY_RESULT reads of
# occlusion (samples-passed) and timestamp queries not preceded by a GL_QUERY_RESULT_AVAILABLE
# answer ("blocking"), buffer uploads, GL object creations and deletions (sync objects apart: the
# fences of the instance rings, gl/stream_ring.hpp, and of the occlusion-query batches,
# culling/occlusion_culler.hpp, are counted as "fences"), waits on a fence with a timeout ("blocking
# fence waits": the culler's async reads poll theirs, a ring waits only when the GPU is a whole ring
# behind); with --json FILE also as
# JSON, with --markdown FILE as a table stamped with the machine and date. --max NAME=N (repeatable) exits 1 when that figure per frame exceeds N (the ctest
# gl_calls_per_frame). The rest of the arguments go to `forest walkthrough` (e.g. --timing queries).
#
#   tools/gl-calls.sh [--forest EXE] [--frames-a 6] [--frames-b 26] [--json FILE] [--markdown FILE] [--max NAME=N ...]
#                     [-- walkthrough flags]
set -euo pipefail
cd "$(dirname "$0")/.."
forest=./build/release/apps/forest
a=6
b=26
json=""
markdown=""
limits=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --forest) forest="$2"; shift 2 ;;
    --frames-a) a="$2"; shift 2 ;;
    --frames-b) b="$2"; shift 2 ;;
    --json) json="$2"; shift 2 ;;
    --markdown) markdown="$2"; shift 2 ;;
    --max) limits+=("$2"); shift 2 ;;
    --) shift; break ;;
    -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
    *) break ;;
  esac
done
command -v apitrace >/dev/null || { echo "gl-calls.sh: apitrace is not installed (tools/setup.sh installs it)" >&2; exit 2; }
[[ "$b" -gt "$a" ]] || { echo "gl-calls.sh: --frames-b $b: expected more than --frames-a $a" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for n in "$a" "$b"; do
  apitrace trace --api egl -o "$work/$n.trace" "$forest" walkthrough --frames "$n" --width 320 --height 180 --no-video \
    --quiet --out "$work/out-$n" "$@" >"$work/log-$n.txt" 2>&1 \
    || { echo "gl-calls.sh: the traced walkthrough failed:" >&2; tail -5 "$work/log-$n.txt" >&2; exit 1; }
  apitrace dump --call-nos=no --color=never "$work/$n.trace" >"$work/$n.txt"
done
device=$(sed -n 's/^\[info\] //p' "$work/log-$b.txt" | head -1)
stamp="Measured $(date +%F) on $(nproc) cores of $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -1); GL: $device."
python3 - "$work/$a.txt" "$work/$b.txt" "$a" "$b" "$json" "$markdown" "$stamp" "$*" "${limits[@]}" <<'EOF'
import collections, json, re, sys

def count(path):
    calls = collections.Counter()
    figures = collections.Counter()
    available = set()   # query ids whose result was reported available since they were last issued
    target_of = {}      # query id -> its target (GL_SAMPLES_PASSED, GL_TIMESTAMP, ...)
    for line in open(path, errors="replace"):
        m = re.match(r"(gl\w+|egl\w+)\((.*)\)", line)
        if not m:
            continue
        name, args = m.group(1), m.group(2)
        calls[name] += 1
        if name == "glCreateQueries":
            t = re.search(r"target = (\w+)", args).group(1)
            for i in re.findall(r"\d+", args.split("ids =")[1]):
                target_of[int(i)] = t
        if name in ("glBeginQuery", "glQueryCounter"):
            available.discard(int(re.search(r"id = (\d+)", args).group(1)))
        if name.startswith("glGetQueryObject"):
            qid = int(re.search(r"id = (\d+)", args).group(1))
            pname = re.search(r"pname = (\w+)", args).group(1)
            value = re.search(r"params = &(\d+)", args)
            if pname == "GL_QUERY_RESULT_AVAILABLE" and value and value.group(1) != "0":
                available.add(qid)
            if pname == "GL_QUERY_RESULT":
                kind = "timestamp" if target_of.get(qid) == "GL_TIMESTAMP" else "occlusion"
                figures[f"{kind} result reads"] += 1
                if qid not in available:
                    figures[f"blocking {kind} result reads"] += 1
                available.discard(qid)
        if re.match(r"gl(Named)?Buffer(Sub)?Data|glMapNamedBufferRange|glMapBufferRange", name):
            figures["buffer uploads"] += 1
        if re.match(r"gl(Create|Gen)\w+", name) and name not in ("glCreateShader", "glCreateProgram"):
            figures["GL object creations"] += 1
        if re.match(r"glDelete\w+", name) and name != "glDeleteSync":
            figures["GL object deletions"] += 1
        if name == "glFenceSync":
            figures["fences"] += 1
        if name == "glClientWaitSync" and re.search(r"timeout = (\d+)", args).group(1) != "0":
            figures["blocking fence waits"] += 1
        if re.match(r"gl(Program)?Uniform(Matrix)?\d", name):
            figures["uniform sets"] += 1
    figures["glFinish"] = calls["glFinish"]
    figures["glGetUniformLocation"] = calls["glGetUniformLocation"]
    return calls, figures

a_path, b_path, a, b, json_path = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
markdown_path, stamp, walk_flags = sys.argv[6], sys.argv[7], sys.argv[8]
limits = [arg.rsplit("=", 1) for arg in sys.argv[9:]]
(ca, fa), (cb, fb) = count(a_path), count(b_path)
frames = b - a
per = lambda x, y: (y - x) / frames
figures = {k: per(fa[k], fb[k]) for k in sorted(set(fa) | set(fb) | {"blocking occlusion result reads", "blocking timestamp result reads",
                                                                      "blocking fence waits", "uniform sets"})}
calls = {k: per(ca[k], cb[k]) for k in set(ca) | set(cb) if cb[k] != ca[k]}
print(f"GL calls per steady-state frame ((calls in {b} frames - calls in {a}) / {frames}):")
headline = ["glFinish", "glGetUniformLocation", "blocking occlusion result reads", "blocking timestamp result reads",
            "occlusion result reads", "timestamp result reads", "buffer uploads", "GL object creations", "GL object deletions",
            "fences", "blocking fence waits", "uniform sets"]
for k in headline:
    print(f"  {k:<34} {figures.get(k, 0.0):10.2f}")
if markdown_path:
    rows = "".join(f"| {k} | {figures.get(k, 0.0):.2f} |\n" for k in headline)
    every = "".join(f"| {k} | {v:.2f} |\n" for k, v in sorted(calls.items(), key=lambda kv: -kv[1]))
    with open(markdown_path, "w") as f:
        f.write(f"# GL calls per steady-state frame\n\n{stamp}\n\n`bash tools/gl-calls.sh -- {walk_flags}`: the default walk traced "
                f"with apitrace for {a} and {b} frames at 320x180; per frame = (calls in {b} frames - calls in {a}) / {frames}.\n\n"
                f"| figure | per frame |\n|---|---:|\n{rows}\nEvery call that changes between the two runs:\n\n"
                f"| call | per frame |\n|---|---:|\n{every}")
print("every call:")
for k, v in sorted(calls.items(), key=lambda kv: -kv[1]):
    print(f"  {k:<44} {v:10.2f}")
if json_path:
    with open(json_path, "w") as f:
        json.dump({"frames": [a, b], "figures": figures, "calls": calls}, f, indent=1, sort_keys=True)
over = 0
for name, limit in limits:
    if name not in figures and name not in calls:
        print(f"gl-calls.sh: --max {name}: no such figure or call", file=sys.stderr)
        sys.exit(2)
    value = figures.get(name, calls.get(name, 0.0))
    if value > float(limit):
        print(f"gl-calls.sh: {name}: {value:.2f} per frame, expected at most {limit}", file=sys.stderr)
        over += 1
sys.exit(1 if over else 0)
EOF
