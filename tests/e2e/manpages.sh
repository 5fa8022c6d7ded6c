#!/usr/bin/env bash
# Every built tool has a man page with the standard sections, and every long
# option its --help prints appears in that page. The pages are the build's
# (build/man/NAME.1: man/NAME.1.in with SYNOPSIS and OPTIONS from the tool's
# --help-man), so this checks the generator and the join too.
source "$(dirname "$0")/lib.sh"

case_every_tool_page_has_every_option() {
pages=${PAGES:-$BIN/../man}
count=0
for tool in img2wc wc2implicit implicit-eval implicit2mesh implicit2tet seg2mesh seg2tet img2poly poly2tri tri2quad quadsmooth meshinfo; do
  [[ -x "$BIN/$tool" ]] || continue
  count=$((count + 1))
  [[ -f "$MAN/$tool.1.in" ]] || fail "$tool has no hand-written page $MAN/$tool.1.in"
  page="$pages/$tool.1"
  [[ -f "$page" ]] || { fail "$tool has no man page $page"; continue; }
  ! grep -q '@SYNOPSIS@\|@OPTIONS@\|@NOTE\|@END@' "$page" || fail "$tool.1 keeps a marker of its .in"
  text=$(sed 's/\\-/-/g; s/\\f[BIRP]//g' "$page")
  for section in NAME SYNOPSIS DESCRIPTION OPTIONS "EXIT STATUS" EXAMPLES "SEE ALSO"; do
    grep -q "^\.SH \"\?$section\"\?" <<<"$text" || fail "$tool.1 lacks section $section"
  done
  help=$("$BIN/$tool" --help) || { fail "$tool --help exited non-zero"; continue; }
  # Ranges and defaults in words: no CLI11 validator text ("FLOAT in [0 -
  # 45]", ":POSITIVE"), no "TEXT" for a file, and --threads shows no number
  # as its default (that would be this machine's core count).
  ! grep -E -- ':(INT|FLOAT) in \[|:POSITIVE|--[a-z-]+ TEXT |--threads N=' <<<"$help" ||
    fail "$tool --help shows CLI11's validator text or a machine's default (above)"
  # Each option of --help is an entry of OPTIONS, not only a word elsewhere.
  options=$(sed -n '/^\.SH "\?OPTIONS/,/^\.SH /p' <<<"$text")
  for opt in $(grep -oE -- '--[a-z][a-z0-9-]*' <<<"$help" | sort -u); do
    grep -qE -- "${opt}([^a-z0-9-]|$)" <<<"$options" || fail "$tool.1 does not document $opt in OPTIONS"
  done
  "$BIN/$tool" --version | grep -q "$tool" || fail "$tool --version does not name the tool"
done
[[ $count == 12 ]] || fail "$count tools checked, not 12"
}

# Exit 3 (output written, a guarantee not met): every page either lists it
# or says there is none; the tools with none are those with no guarantee
# to check (their other tools' exit 3 is run in their own suites).
case_exit_3_listed_or_said_absent() {
  pages=${PAGES:-$BIN/../man}
  for tool in img2wc wc2implicit implicit-eval implicit2mesh implicit2tet seg2mesh seg2tet img2poly poly2tri tri2quad quadsmooth meshinfo; do
    status=$(sed -n '/^\.SH "\?EXIT STATUS/,/^\.SH /p' "$pages/$tool.1" | sed 's/\\-/-/g; s/\\f[BIRP]//g')
    case $tool in
      wc2implicit | implicit-eval)
        grep -q "There is no exit status 3: $tool" <<<"$status" || fail "$tool.1 does not say it has no exit 3" ;;
      *)
        grep -qE '(^|[;,] |^\.B )3( |$)|^3$' <<<"$status" || fail "$tool.1 does not list exit 3" ;;
    esac
  done
}

run_cases "$@"
