#!/usr/bin/env bash
# tests/package/package_test.sh BUILD_DIR — ctest `package` (label package).
#
# Builds the .deb with cpack from a built tree, unpacks it into a scratch root
# (dpkg-deb -x: no root, no container) and uses what it installed, never the
# build tree:
#   - the files are where the executable looks for them (bin/gonio,
#     lib/gonio/gonio_png.so, share/gonio/web/, a man page per subcommand, the
#     completion); fails if an install rule or a subcommand's page is missing;
#   - Depends names the package of every shared library each installed ELF
#     file needs (ldd), and gnuplot; nothing resolves into the build tree or is
#     missing; no RPATH is left;
#   - the installed gonio simulates the installed sample, writes a PNG through
#     the installed module (LD_DEBUG shows which file was loaded: a lookup
#     that fell back to the build tree fails), and serves the installed live
#     page;
#   - every man page renders with `man -l` with no groff warning, names its
#     command and lists that command's options;
#   - the completion sources in a plain bash and completes `gonio sim<TAB>`,
#     `gonio simulate --for<TAB>`, a choice's words, and for every command
#     exactly the options its --help lists.
# Exit 77 (skipped) where a tool is missing; under CI=true that fails (1).
set -uo pipefail

build=$(cd "$1" && pwd)
failures=0
fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}
missing() {
  if [[ ${CI:-} == true || ${CI:-} == 1 ]]; then
    echo "FAIL (CI=true): missing $*" >&2
    exit 1
  fi
  echo "SKIP: missing $*" >&2
  exit 77
}

for tool in cpack dpkg-deb dpkg-shlibdeps dpkg man ldd readelf file; do
  command -v "$tool" >/dev/null || missing "$tool (scripts/setup.sh installs it)"
done
[[ -f $build/CPackConfig.cmake ]] || { echo "FAIL: no $build/CPackConfig.cmake" >&2; exit 1; }

scratch=$(mktemp -d "${TMPDIR:-/tmp}/gonio-package.XXXXXX")
server_pid=""
cleanup() {
  [[ -n $server_pid ]] && kill "$server_pid" 2>/dev/null && wait "$server_pid" 2>/dev/null
  rm -rf "$scratch"
}
trap cleanup EXIT

# --- build and unpack ------------------------------------------------------
if ! cpack -G DEB --config "$build/CPackConfig.cmake" -B "$scratch/package" > "$scratch/cpack.log" 2>&1; then
  cat "$scratch/cpack.log" >&2
  echo "FAIL: cpack -G DEB" >&2
  exit 1
fi
debs=("$scratch"/package/*.deb)
[[ ${#debs[@]} == 1 && -f ${debs[0]} ]] || { echo "FAIL: cpack wrote no single .deb: ${debs[*]}" >&2; exit 1; }
deb=${debs[0]}
echo "package: $(basename "$deb"), $(stat -c %s "$deb") bytes"
depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
root="$scratch/root"
dpkg-deb -x "$deb" "$root" || { echo "FAIL: dpkg-deb -x" >&2; exit 1; }
prefix="$root/usr"
gonio="$prefix/bin/gonio"

mapfile -t commands < <("$gonio" --help | sed -n '/^Commands:/,/^$/p' | sed -n 's/^  \([a-z][a-z0-9-]*\) .*/\1/p')
((${#commands[@]} >= 9)) || fail "the installed gonio --help lists ${#commands[@]} commands: ${commands[*]}"

for f in bin/gonio lib/gonio/gonio_png.so lib/gonio/gonio_cmaes.so share/gonio/web/index.html share/gonio/web/app.js \
         share/bash-completion/completions/gonio share/man/man1/gonio.1.gz \
         share/doc/gonio/examples/downlight/downlight.gltf; do
  [[ -f $prefix/$f ]] || fail "the package has no usr/$f"
done
for c in "${commands[@]}"; do
  [[ -f $prefix/share/man/man1/gonio-$c.1.gz ]] || fail "the package has no man page for '$c'"
done
# Nothing else (the Python module, component python, stays out).
while IFS= read -r f; do
  [[ $f =~ ^usr/(bin/gonio|lib/gonio/[^/]+|share/(gonio/web|man/man1|bash-completion/completions|doc/gonio/examples)/.+)$ ]] ||
    fail "the package holds $f, which packaging/ does not put there"
done < <(cd "$root" && find . -type f | sed 's|^\./||')
if [[ -f $build/tools/gonio-cad ]]; then
  [[ -x $prefix/lib/gonio/gonio-cad ]] || fail "the build has gonio-cad, the package not"
fi

# --- Depends against ldd ---------------------------------------------------
# The package that owns a library file; ldd may name /lib/... where dpkg
# knows /usr/lib/... (merged /usr) or the other way round.
owner() {
  local path=$1 p
  for p in "$path" "$(readlink -f "$path")" "${path/#\/lib\//\/usr\/lib\/}" "${path/#\/usr\/lib\//\/lib\/}"; do
    if out=$(dpkg -S "$p" 2>/dev/null); then
      echo "${out%%:*}" | sed 's/,.*//' | head -n1
      return 0
    fi
  done
  return 1
}
in_depends() {  # PACKAGE: whether Depends names it (alone or as an alternative)
  local alternative
  while read -r alternative; do
    [[ ${alternative%% *} == "$1" ]] && return 0
  done < <(tr ',|' '\n\n' <<< "$depends")
  return 1
}
while IFS= read -r -d '' elf; do
  file -b "$elf" | grep -q '^ELF' || continue
  rel=${elf#"$root"}
  if readelf -d "$elf" | grep -Eq '\((RPATH|RUNPATH)\)'; then
    fail "$rel keeps an RPATH: $(readelf -d "$elf" | grep -E 'RPATH|RUNPATH')"
  fi
  mapfile -t needed < <(readelf -d "$elf" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
  ldd_out=$(ldd "$elf" 2>&1)
  for lib in "${needed[@]}"; do
    # "libX.so.1 => /path (0x...)", or "/path/ld-linux-x86-64.so.2 (0x...)"
    # for the dynamic loader (NEEDED where a program uses one of its symbols).
    path=$(awk -v lib="$lib" '$1 == lib && $2 == "=>" { print $3 }
      $2 != "=>" && substr($1, length($1) - length(lib)) == "/" lib { print $1 }' <<< "$ldd_out" | head -n1)
    if [[ -z $path || $path == "not" ]]; then
      fail "$rel needs $lib, which ldd does not find"
      continue
    fi
    [[ $path == "$build"* || $path == "$root"* ]] && fail "$rel loads $lib from $path"
    if ! pkg=$(owner "$path"); then
      fail "$rel needs $lib ($path), which no Debian package owns"
      continue
    fi
    in_depends "$pkg" || fail "$rel needs $lib from package $pkg, which Depends does not name"
  done
done < <(find "$root" -type f -print0)
in_depends gnuplot-nox || fail "Depends does not name gnuplot-nox (simulate draws its diagrams with gnuplot)"

# --- the installed gonio at work --------------------------------------------
# Run from the scratch folder, with no variable pointing back at the build.
run() { (cd "$scratch" && exec env -u GONIO_WEB_DIR -u GONIO_GNUPLOT "$@"); }
sample="$prefix/share/doc/gonio/examples/downlight/downlight.gltf"
version=$("$gonio" --version 2>&1)
[[ $version =~ ^gonio\ [0-9] ]] || fail "the installed gonio --version says: $version"
# --preview writes DIR/preview.png through the PNG module in lib/gonio/,
# found from the executable: LD_DEBUG=files names the file dlopen loaded.
if run env LD_DEBUG=files "$gonio" simulate "$sample" --out "$scratch/out" --photons 20000 --iterations 2 \
     --threads 2 --no-cache --preview > "$scratch/simulate.log" 2>&1; then
  for f in downlight.ies downlight.ldt downlight.svg farfield.exr report.json preview.png; do
    [[ -s $scratch/out/$f ]] || fail "the installed gonio simulate wrote no $f"
  done
  grep -q "file=$prefix/lib/gonio/gonio_png.so .*dynamically loaded" "$scratch/simulate.log" ||
    fail "gonio simulate --preview did not load $prefix/lib/gonio/gonio_png.so: $(grep -o 'file=[^ ]*gonio_png[^ ]*' "$scratch/simulate.log" | head -n1)"
  [[ $(head -c 8 "$scratch/out/preview.png" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] ||
    fail "gonio simulate --preview wrote no PNG"
  info=$(run "$gonio" info "$scratch/out/downlight.ies" 2>&1)
  grep -qi "flux" <<< "$info" || fail "the installed gonio info cannot read what it simulated: $info"
else
  grep -v "^ *[0-9]*:" "$scratch/simulate.log" | tail -n 20 >&2
  fail "the installed gonio simulate on the installed sample failed"
fi
# The live page: the installed gonio serves share/gonio/web/index.html.
run "$gonio" watch "$sample" --port 0 --photons 2000 --iterations 1 --threads 1 --no-cache \
  > "$scratch/watch.log" 2>&1 &
server_pid=$!
url=""
for _ in $(seq 100); do
  url=$(sed -n 's|^live page: http://\(127.0.0.1:[0-9]*\)/$|\1|p' "$scratch/watch.log")
  [[ -n $url ]] && break
  kill -0 "$server_pid" 2>/dev/null || break
  sleep 0.1
done
if [[ -n $url ]]; then
  page=$(timeout 20 bash -c 'exec 3<>"/dev/tcp/${1%:*}/${1#*:}" &&
    printf "GET /index.html HTTP/1.0\r\nHost: %s\r\nConnection: close\r\n\r\n" "$1" >&3 && cat <&3' _ "$url")
  [[ $page == *"200"* && $page == *"$(head -n1 "$prefix/share/gonio/web/index.html")"* ]] ||
    fail "the installed gonio watch does not serve the installed index.html: ${page:0:200}"
else
  fail "the installed gonio watch did not start its page: $(cat "$scratch/watch.log")"
fi
kill -TERM "$server_pid" 2>/dev/null
for _ in $(seq 100); do
  kill -0 "$server_pid" 2>/dev/null || break
  sleep 0.1
done
if kill -0 "$server_pid" 2>/dev/null; then
  fail "the installed gonio watch did not stop on SIGTERM within 10 s"
  kill -KILL "$server_pid"
fi
wait "$server_pid" 2>/dev/null
server_pid=""

# --- man pages ----------------------------------------------------------------
for page in gonio "${commands[@]/#/gonio-}"; do
  file="$prefix/share/man/man1/$page.1.gz"
  [[ -f $file ]] || continue
  text=$(LC_ALL=C.UTF-8 MANWIDTH=80 man --warnings -l "$file" 2> "$scratch/man.err")
  [[ -s $scratch/man.err ]] && fail "man -l $page.1.gz warns: $(head -n3 "$scratch/man.err")"
  grep -Eq "^ +$page +- " <<< "$text" || fail "man $page has no NAME line for $page"
  if [[ $page == gonio-* ]]; then
    while read -r option; do
      grep -q -- "^       $option\b" <<< "$text" || fail "man $page lacks $option"
    done < <("$gonio" "${page#gonio-}" --help | grep -oE '^  --[a-z0-9-]+' | sed 's/^  //')
  fi
done

# --- bash completion ------------------------------------------------------------
completion="$prefix/share/bash-completion/completions/gonio"
complete_words() {  # WORDS...: what <TAB> after them offers, one per line
  bash --norc --noprofile -c '
    source "$1" || exit 1
    shift
    COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1))
    _gonio
    printf "%s\n" "${COMPREPLY[@]}"' _ "$completion" "$@"
}
[[ $(complete_words gonio sim) == simulate ]] || fail "gonio sim<TAB> gives '$(complete_words gonio sim)'"
complete_words gonio simulate --for | grep -qx -- --format ||
  fail "gonio simulate --for<TAB> gives '$(complete_words gonio simulate --for)'"
[[ $(complete_words gonio simulate --sampler "" | sort | tr '\n' ' ') == "random sobol " ]] ||
  fail "gonio simulate --sampler <TAB> gives '$(complete_words gonio simulate --sampler "")'"
[[ $(complete_words gonio convert --ies-version = | sort | tr '\n' ' ') == "2002 2019 " ]] ||
  fail "gonio convert --ies-version=<TAB> gives '$(complete_words gonio convert --ies-version =)'"
mkdir -p "$scratch/cwd/outdir" && touch "$scratch/cwd/outfile"
[[ $(cd "$scratch/cwd" && complete_words gonio simulate --out out) == outdir ]] ||
  fail "gonio simulate --out out<TAB> offers more than the directory"
[[ $(cd "$scratch/cwd" && complete_words gonio info out | sort | tr '\n' ' ') == "outdir outfile " ]] ||
  fail "gonio info out<TAB> does not offer files"
for c in "${commands[@]}"; do
  want=$("$gonio" "$c" --help | grep -oE '^  --[a-z0-9-]+' | sed 's/^  //' | sort)
  got=$(complete_words gonio "$c" -- | sort)
  [[ $want == "$got" ]] || fail "gonio $c --<TAB> offers [$(tr '\n' ' ' <<< "$got")], its --help lists [$(tr '\n' ' ' <<< "$want")]"
done

if ((failures > 0)); then
  echo "$failures failure(s)" >&2
  exit 1
fi
echo "package: installed into a scratch root and used: all checks passed"
