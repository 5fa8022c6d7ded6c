"""label_partition_check.py IN.nrrd OUT.nrrd STATS.json [TYPE]: checks an
`img2wc --labels` output OUT against its input IN, both NRRD (raw or gzip)
on the same grid (IN: the input grown as OUT, from `--skip-repair`):
the same type (TYPE, the NRRD name, when given) and world geometry; every
output label one of the input's, every input label still present; the
changes the stats report are exactly the voxels that differ, per (from, to)
pair; the grown border background. Well-composedness is checked apart, by
the binary counter (`img2wc OUT --label L --check`)."""
import gzip, json, struct, sys

FORMATS = {'uint8': 'B', 'unsigned char': 'B', 'uchar': 'B', 'int8': 'b', 'signed char': 'b',
           'uint16': 'H', 'unsigned short': 'H', 'ushort': 'H', 'int16': 'h', 'short': 'h',
           'uint32': 'I', 'unsigned int': 'I', 'uint': 'I', 'int32': 'i', 'int': 'i', 'float': 'f', 'double': 'd'}
CANON = {'B': 'uint8', 'b': 'int8', 'H': 'uint16', 'h': 'int16', 'I': 'uint32', 'i': 'int32', 'f': 'float', 'd': 'double'}


def read(path):
    raw = open(path, 'rb').read()
    end = raw.index(b'\n\n') + 2
    hdr = {}
    for line in raw[:end].decode().splitlines()[1:]:
        if ': ' in line and not line.startswith('#'):
            k, v = line.split(': ', 1)
            hdr[k] = v
    data = raw[end:]
    if hdr.get('encoding', 'raw') == 'gzip':
        data = gzip.decompress(data)
    fmt = FORMATS[hdr['type']]
    order = '>' if hdr.get('endian') == 'big' else '<'
    geometry = (hdr['sizes'], hdr.get('space directions'), hdr.get('space origin'))
    return CANON[fmt], [int(s) for s in hdr['sizes'].split()], geometry, Voxels(data, order + fmt)


class Voxels:
    """The voxels as bytes, unpacked a row at a time (large images stay fast)."""
    def __init__(self, data, fmt):
        self.data, self.fmt, self.size = data, fmt, struct.calcsize(fmt)

    def row(self, start, n):
        return struct.unpack('%s%d%s' % (self.fmt[0], n, self.fmt[1]), self.data[start * self.size:(start + n) * self.size])

    def values(self):
        return set(self.data) if self.size == 1 and self.fmt[1] == 'B' else set(self.row(0, len(self.data) // self.size))

    def __getitem__(self, i):
        return self.row(i, 1)[0]


def main():
    a, b, stats = sys.argv[1:4]
    ta, sa, ga, va = read(a)
    tb, sb, gb, vb = read(b)
    assert ta == tb, 'type %s became %s' % (ta, tb)
    if len(sys.argv) > 4:
        assert tb == sys.argv[4], 'output type %s, input %s' % (tb, sys.argv[4])
    assert ga == gb, 'geometry differs: %s vs %s' % (ga, gb)
    d = json.load(open(stats))
    labels_in, labels_out = va.values() - {0}, vb.values() - {0}
    assert labels_out <= labels_in, 'labels not in the input: %s' % sorted(labels_out - labels_in)[:5]
    assert labels_in <= labels_out, 'labels lost: %s' % sorted(labels_in - labels_out)[:5]
    changes = {}
    row = sb[0] * va.size
    for start in range(0, len(va.data), row):
        if va.data[start:start + row] == vb.data[start:start + row]:
            continue
        for x, y in zip(va.row(start // va.size, sb[0]), vb.row(start // va.size, sb[0])):
            if x != y:
                changes[(x, y)] = changes.get((x, y), 0) + 1
    reported = {(c['from'], c['to']): c['voxels'] for c in d['changes']}
    assert changes == reported, 'changes %s, reported %s' % (sorted(changes.items())[:5], sorted(reported.items())[:5])
    assert sum(changes.values()) == d['changed'], 'changed %d, reported %d' % (sum(changes.values()), d['changed'])
    # The grown sides are background.
    n = sb + [1] * (3 - len(sb))
    for axis in range(len(sb)):
        for side, grown in ((0, d['padded_before'][axis]), (n[axis] - 1, d['padded_after'][axis])):
            if not grown:
                continue
            others = [k for k in range(3) if k != axis]
            for u in range(n[others[0]]):
                for w in range(n[others[1]]):
                    c = [0, 0, 0]
                    c[axis], c[others[0]], c[others[1]] = side, u, w
                    v = vb[c[0] + n[0] * (c[1] + n[1] * c[2])]
                    assert v == 0, 'label %d on the grown side %d of axis %d' % (v, side, axis)
    print('ok: %d labels, %d voxels changed' % (len(labels_in), d['changed']))


main()
