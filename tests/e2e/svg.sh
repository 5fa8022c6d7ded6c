#!/usr/bin/env bash
# The SVG pictures of the 2D tools, read as XML: the title line gives the
# mesh's counts, the legend the colour scale (Joe's mu, 0 to 45 degrees) or
# the labels' tints, regions are filled in tints that tell them apart, and
# the frame holds the foreground (all of it) but not the whole image unless
# --svg-whole. On VentricleModel.png (labels 0, 1, 254, 255).
source "$(dirname "$0")/lib.sh"

# The pictures, each made once; a stage reads the one before from the
# shared folder (poly2tri's .node and .poly land there beside its .ele).
v_poly() { expect 0 img2poly "$DATA/VentricleModel.png" v.poly --svg v.svg -q; }
w_poly() { expect 0 img2poly "$DATA/VentricleModel.png" w.poly --svg w.svg --svg-whole -q; }
v_tri() { local p; p=$(shared v.poly v_poly) && expect 0 poly2tri "$p" v.1.ele --svg v.1.svg -q; }
w_tri() { local p; p=$(shared v.poly v_poly) && expect 0 poly2tri "$p" w.1.ele --svg w.1.svg --svg-whole -q; }
v_quad() { local t; t=$(shared v.1.ele v_tri) && expect 0 tri2quad "$t" v.q.ele --svg v.q.svg -q; }
v_smooth() { local q; q=$(shared v.q.ele v_quad) && expect 0 quadsmooth "$q" v.qs.ele --svg v.qs.svg -q; }
# here FILE FUNC...: shared files linked into the case's folder, FILE's
# picture FILE%.*.svg (v.1.ele: v.1.svg) with it.
here() {
  while (($#)); do
    local f; f=$(shared "$1" "$2") || return
    ln -sf "$f" "$1" && ln -sf "${f%.*}.svg" "${1%.*}.svg"
    shift 2
  done
}

# svg_check PYTHON: PYTHON run after the SVG and .ele readers.
svg_check() {
  python3 - > check.txt 2>&1 <<PY || fail "$(cat check.txt)"
import re, xml.etree.ElementTree as ET
N = '{http://www.w3.org/2000/svg}'
def svg(path):
    root = ET.parse(path).getroot()
    title = root.find(N + 'text').text
    clip = root.find('.//' + N + 'clipPath/' + N + 'rect')
    frame = [float(clip.get(k)) for k in ('x', 'y', 'width', 'height')]
    polys = [[tuple(map(float, p.split(','))) for p in e.get('points').split()] for e in root.iter(N + 'polygon')]
    fills = [e.get('fill') for e in root.iter(N + 'polygon')]
    lines = [(float(e.get('x1')), float(e.get('y1')), float(e.get('x2')), float(e.get('y2')), e.get('stroke'))
             for e in root.iter(N + 'line')]
    texts = [e.text for e in root.iter(N + 'text')]
    return dict(title=title, frame=frame, polys=polys, fills=fills, lines=lines, texts=texts, root=root)
def ele(path):
    rows = [l.split('#')[0].split() for l in open(path)]
    rows = [r for r in rows if r]
    n, k, a = map(int, rows[0][:3])
    return [(list(map(int, r[1:1 + k])), float(r[1 + k]) if a else 0.0) for r in rows[1:1 + n]]
inside = lambda f, x, y: f[0] - 0.01 <= x <= f[0] + f[2] + 0.01 and f[1] - 0.01 <= y <= f[1] + f[3] + 0.01
$1
PY
}

# Title: the counts of the mesh drawn.
case_title_gives_the_mesh_counts() {
  here v.1.ele v_tri v.q.ele v_quad || return
  svg_check "
tri, quad = ele('v.1.ele'), ele('v.q.ele')
s1, sq = svg('v.1.svg'), svg('v.q.svg')
assert '%d triangles' % len(tri) in s1['title'], s1['title']
assert '%d quads' % len(quad) in sq['title'] and \"Joe's mu (deg) min\" in sq['title'], sq['title']"
}

# The legend of the mu pictures: the scale's name and its ends 0 and 45.
case_mu_legend_0_to_45() {
  here v.q.ele v_quad v.qs.ele v_smooth || return
  svg_check "
for s in (svg('v.q.svg'), svg('v.qs.svg')):
    assert \"Joe's mu (deg)\" in s['texts'] and '0' in s['texts'] and '45' in s['texts'], s['texts']
    assert s['root'].find('.//' + N + 'linearGradient') is not None"
}

# Regions: one tint each, different between regions (poly2tri fills by region),
# each named in the legend.
case_regions_tinted_apart_and_named() {
  here v.1.ele v_tri || return
  svg_check "
tri, s1 = ele('v.1.ele'), svg('v.1.svg')
tint = {}
for (_, region), fill in zip(tri, s1['fills']):
    tint.setdefault(region, set()).add(fill)
assert len(tint) == 4 and all(len(f) == 1 for f in tint.values()), tint
assert len({next(iter(f)) for f in tint.values()}) == 4, 'two regions share a tint'
assert all('label %d' % r in s1['texts'] for r in tint), s1['texts']"
}

# The frame: every foreground segment (not the image rectangle, marker 1:
# drawn blue) inside it; part of the mesh outside it unless --svg-whole.
case_frame_holds_the_foreground_whole_only_with_svg_whole() {
  here v.1.ele v_tri w.1.ele w_tri v.poly v_poly w.poly w_poly || return
  svg_check "
for name, whole in (('v.1.svg', False), ('w.1.svg', True), ('v.svg', False), ('w.svg', True)):
    s = svg(name)
    fg = [l for l in s['lines'] if l[4] != '#0000cc']
    assert fg and all(inside(s['frame'], l[0], l[1]) and inside(s['frame'], l[2], l[3]) for l in fg), name
    pts = [p for poly in s['polys'] for p in poly] + [(l[0], l[1]) for l in s['lines']]
    out = sum(not inside(s['frame'], x, y) for x, y in pts)
    assert (out == 0) == whole, (name, out)"
}

run_cases "$@"
