#!/usr/bin/env bash
# implicit2mesh's topology certificate on real tissue: every class of the
# bundled brain k-means segmentation (img2wc --label L, wc2implicit,
# implicit2mesh --stats) at the defaults and at the thesis's bounds (ratio 2,
# roughness 60 degrees, no distance bound): wall and CPU
# seconds, triangles, certified or not, the certificate's repairs
# (topology_fallback_rounds / _points), refused TOPOLOGY insertions, and an
# independent check: /work/shared/tools/surfcheck against bdcatopo's
# components of the same well-composed image, where those tools exist.
# With OLD=<an older build's tool folder> (one that takes --roughness in
# radians): brain label 4 at pi/2, ratio 2, no distance bound, timed with
# the old and the new implicit2mesh, one after the other, on the same f.
# ROUGH picks the settings: default; pi2 (what --roughness 1.5708 was when
# the roughness was in radians and the defaults ratio 2 and no distance
# bound: --roughness 90 --ratio 2 --max-distance 0); thesis (ratio 2,
# roughness 60, no distance bound). LABELS="1 2 ..." and ROUGH="default pi2"
# (the default) narrow or widen the sweep. --threads 1 throughout.
#   $1: the build's tool folder.
set -euo pipefail
tools=${1:?tool folder}
src=$(cd "$(dirname "$0")/../.." && pwd)
indep=${INDEP:-/work/shared/tools}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
field() { grep -o "\"$1\": [^,}]*" "$2" | head -1 | sed 's/.*: //'; }
timed() {  # timed OUT-PREFIX command...: wall and CPU seconds in OUT-PREFIX.time
  local t0 t1
  t0=$(date +%s.%N)
  /usr/bin/time -f "%U %S %M" -o "$1.rusage" "${@:2}" > /dev/null 2> "$1.err" || true
  t1=$(date +%s.%N)
  read -r u s m < "$1.rusage"
  echo "$(echo "$t1 - $t0" | bc) $(echo "$u + $s" | bc) $((m / 1024))" > "$1.time"
}
prep() {  # prep L: wc and f of brain label L
  [ -f "$work/$1-f.nrrd" ] && return
  "$tools/img2wc" -q "$src/share/data/brain-kmeans-labels.nii.gz" --label "$1" "$work/$1-wc.nrrd"
  "$tools/wc2implicit" -q "$work/$1-wc.nrrd" "$work/$1-f.nrrd"
}

if [ -n "${OLD:-}" ]; then
  prep 4
  echo "brain label 4, roughness pi/2, ratio 2, no distance bound, old ($OLD) then new ($tools):"
  for which in old new; do
    bin=$tools args=(--roughness 90 --ratio 2 --max-distance 0)
    [ "$which" = old ] && bin=$OLD args=(--roughness 1.5708)
    timed "$work/ab-$which" "$bin/implicit2mesh" -q --threads 1 "$work/4-f.nrrd" "$work/ab-$which.off" "${args[@]}" --stats "$work/ab-$which.json"
    read -r wall cpu mem < "$work/ab-$which.time"
    printf "  %-4s %8.1f s wall %8.1f s CPU %6d MB  triangles %s  certified %s\n" "$which" "$wall" "$cpu" "$mem" \
      "$(field triangles "$work/ab-$which.json")" "$(field topology_matches "$work/ab-$which.json")"
  done
fi

printf "%-6s %-8s %8s %8s %6s %9s %9s %7s %7s %8s %s\n" label rough wall_s cpu_s MB triangles certified fb_rnds fb_pts refused independent
for L in ${LABELS:-1 2 3 4 5}; do
  prep "$L"
  comps=""
  if [ -x "$indep/bdcatopo" ]; then
    /usr/bin/python3 "$indep/bdcatopo" "$work/$L-wc.nrrd" > "$work/$L-bdca.json" || true
    comps="$work/$L-bdca.json"
  fi
  for r in ${ROUGH:-default pi2}; do
    case $r in
      default) opt=() ;;
      pi2) opt=(--ratio 2 --roughness 90 --max-distance 0) ;;
      thesis) opt=(--ratio 2 --roughness 60 --max-distance 0) ;;
      *) echo "certificate.sh: ROUGH: $r is not default, pi2 or thesis" >&2; exit 2 ;;
    esac
    out="$work/$L-$r"
    timed "$out" "$tools/implicit2mesh" -q --threads 1 "$work/$L-f.nrrd" "$out.off" "${opt[@]}" --stats "$out.json"
    read -r wall cpu mem < "$out.time"
    ind=n/a
    if [ -n "$comps" ]; then
      ind=agrees
      /usr/bin/python3 "$indep/surfcheck" "$out.off" --components "$(cat "$comps")" > "$out.surf" || ind=DISAGREES
    fi
    printf "%-6s %-8s %8.1f %8.1f %6d %9s %9s %7s %7s %8s %s\n" "$L" "$r" "$wall" "$cpu" "$mem" \
      "$(field triangles "$out.json")" "$(field topology_matches "$out.json")" \
      "$(field topology_fallback_rounds "$out.json")" "$(field topology_fallback_points "$out.json")" \
      "$(field topology_insertions_refused "$out.json")" "$ind"
    [ -s "$out.err" ] && sed 's/^/    /' "$out.err"
  done
done
