#!/usr/bin/env bash
# Fuzzes the readers with libFuzzer: `scripts/fuzz.sh [SECONDS]` (default 60
# per harness) builds tests/fuzz/ with clang (AddressSanitizer +
# UndefinedBehaviorSanitizer, coverage for libFuzzer) in build-fuzz/, gathers
# the seeds, and runs each harness for SECONDS: the IES reader, the LDT
# reader, the glTF loader (.gltf and .glb, with buffers and light profiles),
# the TM-33 reader (XML), the GLDF reader (ZIP, product.xml and the
# photometries inside), the TM-25 ray-file reader, the measured-BSDF
# readers (BSDF XML: Klems matrices and tensor trees; goniometer CSV),
# Gonio's own scan of a STEP file before OpenCASCADE reads it (stepscan:
# the header and the reference check, about a thousand executions a
# second) and the whole STEP reader (step: OpenCASCADE in process, where
# the build has it, a few executions a second). The two STEP harnesses share one
# harness's time (below) and libFuzzer's dictionary tests/fuzz/step.dict.
# Fails on any finding (crash, sanitizer report, leak, timeout, broken round
# trip) and names the input that caused it (build-fuzz/findings/); a fault
# inside OpenCASCADE (STEP harness) fails only where gonio, which runs it in
# a helper process, does not contain it (below).
#
# Seeds (build-fuzz/seeds/, made here, never committed): the corpus files in
# ../shared/corpus, the sample profiles and models, the sample curves
# converted to TM-33 and GLDF (each photometry format inside) by the build's
# gonio, tests/fuzz/seeds/, and the hand-made hostile inputs of the reader
# tests (gonio_io_tests and gonio_model_tests run once with
# $GONIO_FUZZ_SEEDS set, in build/). What the fuzzer finds new stays in
# build-fuzz/corpus/ for the next run.
# $GONIO_FUZZ_ONLY (ies, ldt, gltf, tm33, gldf, tm25, bsdf, stepscan or step;
# several separated by spaces) runs those harnesses only. $GONIO_FUZZ_STEP_SEEDS,
# a folder, adds the STEP files in it to the STEP harnesses' seeds (the
# CAx-IF files of docs/cad.md, fetched for a local campaign, never committed).
#
# Runs repeat: libFuzzer's random seed is $GONIO_FUZZ_SEED, by default a
# hash of the committed code (not of README.md or docs/); each harness
# stops after a fixed number of executions ($GONIO_FUZZ_RUNS, default
# 150,000, about what 60 s give here) or SECONDS, whichever comes first;
# the seeds are the same bytes on every run ($SOURCE_DATE_EPOCH below); and
# the scheduling that depends on execution times is off (-entropic=0,
# -reload=0). From a fresh clone (no build-fuzz/corpus yet) a run then makes
# the same inputs in the same order on any machine, a slower machine a
# prefix of them (address-space randomisation off, below). So code whose
# run is clean here is clean in CI, and a finding in CI is found again here
# with the seed it prints. New inputs come from new code's seeds and from long
# campaigns (DEVELOPERS.md, Build: scripts/fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
jobs=$(nproc 2>/dev/null || echo 2)
harnesses=(ies ldt gltf tm33 gldf tm25 bsdf stepscan step)
if [ -n "${GONIO_FUZZ_ONLY:-}" ]; then read -ra harnesses <<<"$GONIO_FUZZ_ONLY"; fi

bash scripts/setup.sh

echo "== fuzz build (clang, libFuzzer, AddressSanitizer + UndefinedBehaviorSanitizer)"
# ccache hands the compiler the sources' paths relative to the checkout, so
# that no path of it lands in the binaries (the sanitizers' metadata keeps
# the paths the compiler is given): the same code, the same binary, in any
# clone.
export CCACHE_BASEDIR="$PWD"
bash scripts/configure.sh build-fuzz -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=Release -DGONIO_FUZZ=ON \
  -DGONIO_BUILD_TESTS=OFF -DGONIO_BUILD_BENCHMARKS=OFF
cmake --build build-fuzz -j"$jobs" --target "${harnesses[@]/#/gonio_fuzz_}"

echo "== seeds"
seeds=build-fuzz/seeds
rm -rf "$seeds"
mkdir -p "$seeds"/{ies,ldt,gltf,tm33,gldf,tm25,bsdf,stepscan,step} build-fuzz/findings
corpus=${GONIO_CORPUS:-../shared/corpus}
if [ -d "$corpus" ]; then
  find "$corpus" -type f -iname '*.ies' -exec cp {} "$seeds/ies/" \;
  find "$corpus" -type f -iname '*.ldt' -exec cp {} "$seeds/ldt/" \;
  # Ray files are megabytes: their header and first 100 rays of 28 bytes,
  # the ray count set to 100 (bytes 20-27, little-endian).
  find "$corpus" -type f -iname '*.tm25ray' | while read -r ray_file; do
    seed_file="$seeds/tm25/$(basename "$ray_file")"
    head -c 39728 "$ray_file" >"$seed_file"
    printf 'd\0\0\0\0\0\0\0' | dd of="$seed_file" bs=1 seek=20 conv=notrunc status=none
  done
elif [ "${CI:-}" = true ] || [ "${CI:-}" = 1 ]; then
  echo "fuzz: the corpus ($corpus) is missing; under CI=true that is a failure" >&2
  exit 1
else
  echo "fuzz: the corpus ($corpus) is missing: seeding without it" >&2
fi
cp samples/curves/*.ies "$seeds/ies/"
cp samples/curves/*.ldt "$seeds/ldt/"
cp tests/fuzz/seeds/gltf/* "$seeds/gltf/"
# The reader tests' hand-made inputs (tests/support offer_fuzz_seed) and the
# sample models, from the Release build.
bash scripts/build.sh --target gonio gonio_io_tests gonio_model_tests gonio_samples >/dev/null
GONIO_FUZZ_SEEDS="$PWD/$seeds" ./build/tests/gonio_io_tests --gtest_brief=1 \
  --gtest_filter='Ies*:Ldt*:Tm33*:Gldf*:Zip*:Tm25*:Bsdf*' >/dev/null
# The dates the converter writes (GLDF creation time, ZIP entry times) are
# fixed, so that the seeds are the same bytes on every run.
export SOURCE_DATE_EPOCH=1764620000
# The sample curves as TM-33 documents and as GLDF containers, with the
# curve inside as EULUMDAT (from .ldt) and IES (from .ies), and one with
# TM-33 inside.
convert() {
  ./build/tools/gonio convert "$1" "$2" --quiet >/dev/null 2>&1 || { echo "fuzz: cannot convert $1 to $2" >&2; exit 1; }
}
for curve in samples/curves/*.ies samples/curves/*.ldt; do
  name=$(basename "$curve")
  convert "$curve" "$seeds/tm33/${name%.*}-${name##*.}.xml"
  convert "$curve" "$seeds/gldf/${name%.*}-${name##*.}.gldf"
done
convert "$seeds/tm33/downlight-ies.xml" "$seeds/gldf/downlight-xml.gldf"
GONIO_FUZZ_SEEDS="$PWD/$seeds" ./build/tests/gonio_model_tests --gtest_brief=1 \
  --gtest_filter='Gltf*' >/dev/null
# STEP (both harnesses): the CAD test parts FreeCAD and OpenCASCADE's DRAW
# write (tests/cad/, made by the CAD suite in build/test-data/cad/) and the
# suite's hand-made broken files.
if [[ " ${harnesses[*]} " == *" step "* || " ${harnesses[*]} " == *" stepscan "* ]]; then
  bash scripts/build.sh --target gonio_cad_tests >/dev/null
  GONIO_FUZZ_SEEDS="$PWD/$seeds" ./build/tests/gonio_cad_tests --gtest_brief=1 \
    --gtest_filter='CadHostile*:CadStep.FreeCad*:StepReferences*' >/dev/null
  find build/test-data/cad -maxdepth 1 -type f \( -name '*.step' -o -name '*.igs' \) -size -400k \
    -exec cp {} "$seeds/step/" \;
  if [ -n "${GONIO_FUZZ_STEP_SEEDS:-}" ]; then
    find "$GONIO_FUZZ_STEP_SEEDS" -maxdepth 1 -type f \( -iname '*.stp' -o -iname '*.step' \) -size -512k \
      -exec cp {} "$seeds/step/" \;
  fi
  find "$seeds/step" -type f -exec cp {} "$seeds/stepscan/" \;
fi
# Each sample model with its buffer as the side file (tests/fuzz/gltf_fuzzer.cpp).
for model in build/samples/*/*.gltf; do
  stem=$(basename "$model" .gltf)
  bin="${model%.gltf}.bin"
  if [ -f "$bin" ] && [ "$(stat -c %s "$bin")" -le 393216 ]; then
    { sed "s/\"$stem\.bin\"/\"fuzz.bin\"/" "$model"; printf '\n#gonio-fuzz-file\n'; cat "$bin"; } \
      >"$seeds/gltf/sample-$stem.gltf"
  fi
done
for h in "${harnesses[@]}"; do
  echo "fuzz: $h: $(find "$seeds/$h" -type f | wc -l) seeds"
done

# The seed follows the code, not the documents: a commit that changes only
# README.md or docs/ fuzzes exactly as its parent did.
seed=${GONIO_FUZZ_SEED:-}
if [ -z "$seed" ]; then
  code=$(git ls-tree -r HEAD -- CMakeLists.txt io photometry sim tools tests samples scripts 2>/dev/null |
    sha1sum | cut -c1-7)
  seed=$((16#$code))
fi
runs=${GONIO_FUZZ_RUNS:-150000}
echo "fuzz: seed $seed, at most $runs executions or ${seconds} s per harness, the two STEP harnesses ${seconds} s together (GONIO_FUZZ_SEED=$seed repeats this run)"

# A run repeats only where the addresses it sees repeat: comparisons of
# pointers feed libFuzzer's comparison-guided mutations. So the harnesses
# run without address-space randomisation (setarch -R) and with the same few
# environment variables (they sit on the stack), and their binaries carry no
# path of the checkout (above). Measured: two GLDF runs of 150,000
# executions with the same seed parted after ~12,800 with randomisation and
# agreed to the end without it.
fixed=(env -i PATH=/usr/bin:/bin SOURCE_DATE_EPOCH="$SOURCE_DATE_EPOCH"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:allocator_may_return_null=1
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1)
arch=()
if setarch "$(uname -m)" -R true 2>/dev/null; then
  arch=(setarch "$(uname -m)" -R)
else
  echo "fuzz: setarch -R is not allowed here: addresses are random, so runs may not repeat" >&2
fi
# The STEP harness runs OpenCASCADE in this process; gonio runs it in the
# helper gonio-cad, where a crash or hang is an error message. So a finding
# whose stack is OpenCASCADE's (scripts/fuzz_triage.py) is checked there: a
# crash must make `gonio simulate` end with an error naming the file, exit 1
# (a hang is the helper's time limit, CadHostile.ACrashingOrHangingReader*);
# then it is reported as contained, kept in build-fuzz/findings/, and the
# harness goes on with the next seed for the time left. A fault in Gonio's
# own code, or one gonio does not contain, fails.
contained() {
  local finding=$1 dir
  dir=$(mktemp -d)
  cp "$finding" "$dir/finding.step"
  set +e
  timeout 300 ./build/tools/gonio simulate "$dir/finding.step" --out "$dir/out" >"$dir/stdout" 2>"$dir/stderr"
  local rc=$?
  set -e
  local said
  said=$(head -c 400 "$dir/stderr")
  rm -rf "$dir"
  if [ "$rc" -eq 1 ] && [[ "$said" == "gonio: $dir/finding.step: "* ]]; then
    echo "fuzz: step: gonio says: ${said#"gonio: $dir/"}"
    return 0
  fi
  echo "fuzz: step: gonio did not contain it (exit $rc): $said" >&2
  return 1
}

# One harness: its run, and the next seeds after contained OpenCASCADE
# faults; 1 on a finding.
fuzz_one() {
  local h=$1 time=$2 log max_len lsan started left round rc execs last finding verdict dict
  echo "== fuzz $h (${time} s)"
  mkdir -p "build-fuzz/corpus/$h"
  log="build-fuzz/fuzz-$h.log"
  # Inputs up to 128 KiB (the largest corpus file is 100 KB; the unit tests
  # cover the huge ones), models with their buffer up to 512 KiB. The STEP
  # scan's up to 4 KiB (the seeds' first 4 KiB: the header and some 60
  # entities): it costs about 100 ns a byte under libFuzzer's comparison
  # tracing, so whole parts would make it five times slower (docs/cad.md).
  max_len=131072
  if [ "$h" = gltf ] || [ "$h" = step ]; then max_len=524288; fi
  if [ "$h" = stepscan ]; then max_len=4096; fi
  dict=()
  if [ "$h" = step ] || [ "$h" = stepscan ]; then dict=(-dict=tests/fuzz/step.dict); fi
  # OpenCASCADE keeps singletons alive to the end (its document application,
  # its messenger): LeakSanitizer is told to ignore what its libraries hold.
  lsan=()
  if [ "$h" = step ]; then
    printf 'leak:libTK\n' >build-fuzz/lsan-occt.supp
    lsan=(LSAN_OPTIONS=suppressions="$PWD/build-fuzz/lsan-occt.supp")
  fi
  started=$(date +%s)
  left=$time
  round=0
  while :; do
    set +e
    "${fixed[@]}" "${lsan[@]}" "${arch[@]}" "./build-fuzz/tests/fuzz/gonio_fuzz_$h" "build-fuzz/corpus/$h" "$seeds/$h" \
      -seed="$((seed + round))" -runs="$runs" -reload=0 -entropic=0 -max_total_time="$left" -timeout=25 -rss_limit_mb=4096 \
      -max_len="$max_len" "${dict[@]}" -print_final_stats=1 -artifact_prefix="build-fuzz/findings/$h-" >"$log" 2>&1
    rc=$?
    set -e
    # Executions, coverage (edges) and features at the end, from libFuzzer's
    # own lines.
    execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
    last=$(grep -E '#[0-9]+.*cov: ' "$log" | tail -1 || true)
    echo "fuzz: $h: ${execs:-?} executions (seed $((seed + round))); last status: ${last:-none}"
    [ "$rc" -eq 0 ] && break
    finding=$(grep -o 'Test unit written to [^ ]*' "$log" | tail -1 | sed 's/Test unit written to //' || true)
    verdict=$(python3 scripts/fuzz_triage.py "$log")
    if [ "$h" = step ] && [ "${verdict%% *}" = opencascade ] && [ -n "$finding" ] &&
      { grep -q 'ERROR: libFuzzer: timeout' "$log" || contained "$finding"; }; then
      echo "fuzz: step: a fault inside OpenCASCADE (${verdict#* }), contained by gonio-cad; the input is $finding"
      cp "$log" "build-fuzz/fuzz-$h-contained-$round.log"
      round=$((round + 1))
      left=$((time - ($(date +%s) - started)))
      if [ "$left" -lt 5 ]; then rc=0; break; fi
      continue
    fi
    break
  done
  if [ "$rc" -ne 0 ]; then
    echo "fuzz: $h: FINDING (exit $rc) in ${verdict#* }; the log is $log:" >&2
    grep -E 'ERROR|SUMMARY|fuzz finding|Test unit written|runtime error' "$log" | head -20 >&2 || true
    return 1
  fi
  return 0
}
# The harnesses of one lane, one after another. Each gets SECONDS (or its
# $runs executions, where they come sooner), but for the two STEP harnesses,
# which share one harness's time in the same lane: the scan (stepscan),
# about a thousand executions a second on Gonio's own code, a third of it;
# OpenCASCADE's harness (step), a few executions a second, what is left of
# the lane's budget (SECONDS per harness, the two counted as one) when its
# turn comes, and never less than the other two thirds: the time harnesses
# before it saved by reaching $runs early (tm25 in CI) goes to it, and the
# lane ends when it would have ended with eight harnesses.
lane() {
  local h st=0 both=0 slots=$# started scan_time step_time
  if [[ " $* " == *" stepscan "* && " $* " == *" step "* ]]; then
    both=1
    slots=$((slots - 1))
  fi
  scan_time=$seconds
  if [ "$both" = 1 ]; then scan_time=$(((seconds + 2) / 3)); fi
  started=$(date +%s)
  for h in "$@"; do
    case $h in
      stepscan) fuzz_one "$h" "$scan_time" || st=1 ;;
      step)
        step_time=$seconds
        if [ "$both" = 1 ]; then
          step_time=$((slots * seconds - ($(date +%s) - started)))
          if [ "$step_time" -lt $((seconds - scan_time)) ]; then step_time=$((seconds - scan_time)); fi
        fi
        fuzz_one "$h" "$step_time" || st=1
        ;;
      *) fuzz_one "$h" "$seconds" || st=1 ;;
    esac
  done
  return "$st"
}

# Two harnesses at a time, one per core (each is one process), in two
# lanes whose output is shown when both have ended, the two STEP harnesses
# (last in the list) in the same one; alone where the machine has one core
# or one harness is asked for.
status=0
n=${#harnesses[@]}
slots=$n
if [[ " ${harnesses[*]} " == *" stepscan "* && " ${harnesses[*]} " == *" step "* ]]; then slots=$((n - 1)); fi
if [ "$jobs" -ge 2 ] && [ "$slots" -ge 2 ]; then
  half=$(((slots + 1) / 2))
  lane "${harnesses[@]:0:half}" >build-fuzz/lane-1.log 2>&1 &
  first=$!
  lane "${harnesses[@]:half}" >build-fuzz/lane-2.log 2>&1 &
  second=$!
  wait "$first" || status=1
  wait "$second" || status=1
  cat build-fuzz/lane-1.log build-fuzz/lane-2.log
else
  lane "${harnesses[@]}" || status=1
fi
exit "$status"
