# The e2e harness, sourced by every tests/e2e/SUITE.sh.
#
# A suite defines one function per case, case_WHAT, named after what it
# checks, and ends with `run_cases "$@"`. tests/CMakeLists.txt makes each
# case its own ctest entry e2e.SUITE.WHAT (`bash SUITE.sh WHAT`); `bash
# SUITE.sh` alone runs every case, in order. A case runs in a subshell in its
# own empty folder $TMP/WHAT (TMPDIR is its .tmp, which must end empty),
# under `set -u` but not `set -e`: checks are `COND || fail "why"`, which
# prints "FAIL e2e.SUITE.WHAT: why" and goes on
# (`die` also ends the case); the next cases run whatever happens. Tools run
# through `expect STATUS TOOL ARGS...` (stdin $IN or /dev/null, stdout $OUT
# or out.txt, stderr err.txt): a wrong status fails naming the command and
# shows the tool's stderr, and so does any stderr line of a built tool that
# does not start with "TOOL: ". Inputs come from fixed seeds (python's
# random.Random, never awk's srand or /dev/urandom) or small committed files;
# one that several cases need is made once by `shared FILE FUNC`.
#
# Adopting an old-style script: put each block in a case_WHAT function, run
# its tools with expect instead of `tool -q ... || fail`, drop `set -e` and
# the final "ok" line, source this file, end with `run_cases "$@"`.
set -u
SUITE=$(basename "${BASH_SOURCE[1]}" .sh)
E2E=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)  # tests/e2e, for its checkers
SCRIPT=$E2E/$(basename "${BASH_SOURCE[1]}")
: "${BIN:?BIN: the tools folder}" "${TMP:?TMP: a scratch folder}"
CASE=${CASE:-} CASE_DIR=${CASE_DIR:-}

fail() {  # fail WHY...: the case fails, and goes on
  # A reason of several lines (a checker's output) keeps its later lines
  # under the FAIL line, marked as the harness's.
  local why="$*"
  echo "FAIL e2e.$SUITE.$CASE: ${why%%$'\n'*}" >&2
  [[ $why != *$'\n'* ]] || sed 's/^/    | /' <<< "${why#*$'\n'}" >&2
  : > "$CASE_DIR/.failed"
  return 0
}
die() { fail "$@"; exit 1; }

# expect STATUS TOOL ARGS...: TOOL is a built tool ($BIN/TOOL) or a command.
expect() {
  local want=$1 tool=$2; shift 2
  local exe=$tool why=""
  [[ -x $BIN/$tool ]] && exe=$BIN/$tool
  "$exe" "$@" < "${IN:-/dev/null}" > "${OUT:-out.txt}" 2> err.txt
  local got=$?
  [[ $got == "$want" ]] || why="exit $got, want $want"
  if [[ $exe == "$BIN/$tool" ]] && grep -qv "^$tool: " err.txt; then
    why="${why:+$why; }a stderr line does not start with \"$tool: \""
  fi
  [[ -z $why ]] && return 0
  fail "$tool $*: $why"
  sed 's/^/    | /' err.txt >&2
  return 1
}

# shared FILE FUNC [ARGS...]: $TMP/shared/FILE, made by FUNC run in a
# folder of its own, then moved into $TMP/shared with FUNC's other files;
# once for the cases of a suite (under a lock of FILE's: they may run in
# parallel, and FUNC may need another shared file), again when a tool or
# the suite is newer than FILE. Prints its path.
shared() {
  local dir=$TMP/shared file=$1; shift
  mkdir -p "$dir"
  (
    flock 9
    if [[ -e $dir/$file ]]; then
      [[ -z $(find "$BIN" "$SCRIPT" -maxdepth 1 -type f -newer "$dir/$file") ]] && exit 0
      rm -f "$dir/$file"
    fi
    work=$(mktemp -d "$dir/.work.XXXXXX")
    cd "$work" && "$@" >&2 && [[ -e $file ]] && for f in *; do mv -f "$f" "$dir/"; done
    rm -rf "$work"
  ) 9> "$dir/.$file.lock"
  [[ -e $dir/$file ]] || die "could not make the shared input $file"
  echo "$dir/$file"
}

# refused TOOL PATTERN IN [OUT]: bad input refused: exit 1 within 10 s, one
# stderr line "TOOL: NAMED: ...PATTERN" (NAMED defaults to IN: the file the
# message must name), OUT not created.
refused() {
  local tool=$1 pattern=$2 in=$3 out=${4:-} named=${NAMED:-$3}
  rm -f err
  [[ -n $out ]] && rm -f "$out"
  local start=$SECONDS
  timeout 20 "$BIN/$tool" "$in" ${out:+"$out"} 2>err </dev/null >/dev/null
  local rc=$? took=$((SECONDS - start))
  [[ $rc == 1 ]] || fail "$tool $in: exit $rc, expected 1 ($(head -c 300 err))"
  [[ $(wc -l <err) == 1 ]] || fail "$tool $in: $(wc -l <err) lines on stderr, expected 1"
  grep -q "^$tool: $named: .*$pattern" err || fail "$tool $in: message '$(head -c 300 err)' does not match '$tool: $named: ...$pattern'"
  ((took <= 10)) || fail "$tool $in: took $took s"
  [[ -z $out || ! -e $out ]] || fail "$tool $in: left $out"
}

# json FILE KEY[.KEY...]: a value of a JSON file (- for stdin), as python's str().
json() {
  python3 -c 'import json, sys
d = json.load(sys.stdin if sys.argv[1] == "-" else open(sys.argv[1]))
for k in sys.argv[2].split("."): d = d[int(k)] if isinstance(d, list) else d[k]
print(d)' "$1" "$2"
}
# A python that has the module, or none: the pyenv python on PATH may not
# see Debian's python3-vtk9 / python3-meshio.
python_with() {
  for py in python3 /usr/bin/python3; do
    if command -v "$py" > /dev/null && "$py" -c "import $1" 2> /dev/null; then echo "$py"; return; fi
  done
}
# count FILE: the first number of a Triangle file (nodes or elements).
count() { grep -v '^ *#' "$1" | head -1 | cut -d' ' -f1; }

# whole FILE: an .svg, .msh or legacy .vtk file ends where its format says
# (a writer cut short fails): </svg>, $End..., the last data block's count.
whole() {
  case $1 in
    *.svg) [[ $(tail -n 1 "$1") == "</svg>" ]] ;;
    *.msh) [[ $(tail -n 1 "$1") == \$End* ]] ;;
    *.vtk) awk '/^(CELL|POINT)_DATA/ { n = $2 } /^LOOKUP_TABLE/ { k = 0; next } { k++ } END { exit !(n > 0 && k == n) }' "$1" ;;
    *) return 1 ;;
  esac || { fail "$1 is cut short"; return 1; }
}

# The built tools' names, as an extended regular expression's alternatives.
TOOLS=$(cd "$BIN" && for t in *; do [[ -f $t && -x $t ]] && printf '%s|' "$t"; done | sed 's/|$//')

run_cases() {
  local cases=("$@") c failed=0
  ((${#cases[@]})) || mapfile -t cases < <(sed -n 's/^case_\([A-Za-z0-9_]*\) *().*/\1/p' "$SCRIPT")
  for c in "${cases[@]}"; do
    local dir=$TMP/$c
    rm -rf "$dir"; mkdir -p "$dir"
    if ! declare -F "case_$c" > /dev/null; then
      echo "FAIL e2e.$SUITE.$c: no such case"; failed=1; continue
    fi
    mkdir "$dir/.tmp"
    # The case's stderr, kept and then shown: every line must be the
    # harness's (FAIL, "    | ") or start with a built tool's name, so a
    # tool run outside expect (a pipe, a setup step) is checked too.
    ( CASE=$c CASE_DIR=$dir; export TMPDIR=$dir/.tmp; cd "$dir" && "case_$c" ) 2> "$dir/.stderr"
    cat "$dir/.stderr" >&2
    local stray
    stray=$(grep -vE "^(FAIL e2e\.|    \| |($TOOLS): )" "$dir/.stderr" | head -3)
    [[ -z $stray ]] || { CASE=$c CASE_DIR=$dir fail "a stderr line does not start with a tool's name: $stray"; }
    [[ -z $(ls -A "$dir/.tmp") ]] || { CASE=$c CASE_DIR=$dir fail "left in TMPDIR: $(ls -A "$dir/.tmp")"; }
    if [[ -e $dir/.failed ]]; then echo "FAIL e2e.$SUITE.$c"; failed=1; else echo "PASS e2e.$SUITE.$c"; fi
  done
  exit $failed
}
