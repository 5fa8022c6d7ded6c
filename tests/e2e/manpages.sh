#!/usr/bin/env bash
# Every built tool has a man page with the standard sections, and every long
# option its --help prints appears in that page.
set -u
fail=0
count=0
for tool in img2wc wc2implicit implicit-eval implicit2mesh img2poly poly2tri tri2quad quadsmooth meshinfo; do
  [[ -x "$BIN/$tool" ]] || continue
  count=$((count + 1))
  page="$MAN/$tool.1"
  if [[ ! -f "$page" ]]; then echo "FAIL: $tool has no man page $page"; fail=1; continue; fi
  text=$(sed 's/\\-/-/g; s/\\f[BIRP]//g' "$page")
  for section in NAME SYNOPSIS DESCRIPTION OPTIONS "EXIT STATUS" EXAMPLES "SEE ALSO"; do
    grep -q "^\.SH \"\?$section\"\?" <<<"$text" || { echo "FAIL: $tool.1 lacks section $section"; fail=1; }
  done
  help=$("$BIN/$tool" --help) || { echo "FAIL: $tool --help exited non-zero"; fail=1; continue; }
  for opt in $(grep -oE -- '--[a-z][a-z0-9-]*' <<<"$help" | sort -u); do
    grep -qE -- "${opt}([^a-z0-9-]|$)" <<<"$text" || { echo "FAIL: $tool.1 does not document $opt"; fail=1; }
  done
  "$BIN/$tool" --version | grep -q "$tool" || { echo "FAIL: $tool --version does not name the tool"; fail=1; }
done
echo "checked $count tools"
[[ $count -gt 0 ]] || { echo "FAIL: no tool built"; exit 1; }
exit $fail
