#!/usr/bin/env bash
# The 2D pipeline end to end on the bundled images (README's chains):
# img2poly | poly2tri | tri2quad | quadsmooth, each quad mesh checked by
# quad_check.py (strictly convex, edge to edge, the triangles' area and
# region areas kept; tri2quad's output alone is quadsmooth's input check) and its quality measured by meshinfo, not taken from
# the tools' --stats. A failure here with the tools' own suites passing is
# an interaction between stages.
source "$(dirname "$0")/lib.sh"
QC=$E2E/quad_check.py
IMAGES=("VentricleModel.png:--threshold 128" "BinaryImage.png:" "BrainT1Slice.png:--threshold 100"
        "RatLungSlice1.mha:--threshold 100")
# q MESH KEY: meshinfo's quad quality entry, meshinfo run once a mesh.
q() { [[ -s $1.json ]] || "$BIN/meshinfo" --json "$1" > "$1.json"; json "$1.json" "quad_quality.$2"; }

# chain IMAGE OPTS NAME [POLY2TRI OPTIONS -- TRI2QUAD OPTIONS]: NAME.qs.ele.
chain() {
  local image=$1 opts=$2 name=$3; shift 3
  local p=() t=()
  while (($#)) && [[ $1 != -- ]]; do p+=("$1"); shift; done
  (($#)) && shift && t=("$@")
  # q() keeps meshinfo's report by file name, and a loop reuses the name.
  rm -f "$name".*.json
  # shellcheck disable=SC2086  # opts: an option and its value
  expect 0 img2poly "$DATA/$image" "$name.poly" $opts &&
    expect 0 poly2tri "$name.poly" "$name.1.ele" "${p[@]}" &&
    expect 0 tri2quad "$name.1.ele" "$name.q.ele" "${t[@]}" &&
    expect 0 quadsmooth "$name.q.ele" "$name.qs.ele" || return 1
  python3 "$QC" "$name.qs.ele" "$name.1.ele" > qc.txt 2>&1 || fail "$image: $name.qs.ele: $(cat qc.txt)"
}

# The issue's bar: no quad with mu below 5 degrees; on the ventricles also at
# least half of the quads with every angle in [45, 135] and 5 degrees more
# mean mu than tri2quad's (tri2quad gives about 0.02, 35% and 14; quadsmooth
# 15, 75% and 24). The thin strips between constraint curves of the lung and
# the brain need the pair splits into four.
case_real_images_quads_mu_at_least_5() {
  local spec image opts
  for spec in "${IMAGES[@]}"; do
    IFS=: read -r image opts <<< "$spec"
    chain "$image" "$opts" r || continue
    python3 -c "import sys; sys.exit(not float(sys.argv[1]) >= 5)" "$(q r.qs.ele min_mu)" || fail "$image: min mu $(q r.qs.ele min_mu)"
    if [[ $image == VentricleModel.png ]]; then
      python3 -c "import sys; s, b, a = map(float, sys.argv[1:]); sys.exit(not (s >= 0.5 and a >= b + 5))" \
        "$(q r.qs.ele angles_45_135)" "$(q r.q.ele mean_mu)" "$(q r.qs.ele mean_mu)" ||
        fail "ventricles: share in [45,135] $(q r.qs.ele angles_45_135), mean mu $(q r.q.ele mean_mu) -> $(q r.qs.ele mean_mu)"
    fi
  done
}

# poly2tri --lattice (equilateral triangles, which tri2quad pairs into
# 60-degree rhombi) gives the ventricles a higher mean mu after quadsmooth
# than a Delaunay refinement to the same edge length, with fewer quads and
# the same bar on the worst quad.
case_lattice_beats_max_edge_on_the_ventricles() {
  chain VentricleModel.png "--threshold 128" lattice --lattice 4 || return
  chain VentricleModel.png "--threshold 128" edge --max-edge 4 || return
  python3 -c "import sys; lm, em, lq, eq, lmin = map(float, sys.argv[1:]); sys.exit(not (lm > em and lq < eq and lmin >= 5))" \
    "$(q lattice.qs.ele mean_mu)" "$(q edge.qs.ele mean_mu)" "$(count lattice.qs.ele)" "$(count edge.qs.ele)" \
    "$(q lattice.qs.ele min_mu)" ||
    fail "--lattice 4: mean mu $(q lattice.qs.ele mean_mu) in $(count lattice.qs.ele) quads;" \
         "--max-edge 4: $(q edge.qs.ele mean_mu) in $(count edge.qs.ele)"
}

# The issue's bar on mean mu (30) through the quad-friendly chain: a square
# lattice (poly2tri --square-lattice 2) whose right triangles tri2quad
# merges into squares first (--pair-above 40). The thesis's BFS pairing
# alone turns much of such a lattice into 45-degree parallelograms, which
# tri2quad's output shows (quadsmooth makes up much of the gap after).
case_square_lattice_pairs_first_mean_mu_30() {
  local spec image opts
  for spec in "${IMAGES[@]}"; do
    IFS=: read -r image opts <<< "$spec"
    chain "$image" "$opts" s0 --square-lattice 2 || continue
    chain "$image" "$opts" s40 --square-lattice 2 -- --pair-above 40 || continue
    python3 -c "import sys; m, a, p, f = map(float, sys.argv[1:]); sys.exit(not (m >= 5 and a >= 30 and f > p + 2))" \
      "$(q s40.qs.ele min_mu)" "$(q s40.qs.ele mean_mu)" "$(q s0.q.ele mean_mu)" "$(q s40.q.ele mean_mu)" ||
      fail "$image, square lattice: min mu $(q s40.qs.ele min_mu), mean $(q s40.qs.ele mean_mu);" \
           "tri2quad alone: mean $(q s40.q.ele mean_mu) pairs first, $(q s0.q.ele mean_mu) without"
  done
}

run_cases "$@"
