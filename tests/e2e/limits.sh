#!/usr/bin/env bash
# Limits before allocation: headers that declare more data than their file
# can hold, or more than the machine's memory, are refused by every tool
# that reads them within seconds, with one line naming the tool and the
# file, exit status 1 and no output file. The files are made here, small.
source "$(dirname "$0")/lib.sh"

# NRRD headers over a few bytes of data.
nrrd() {  # FILE TYPE SIZES ENCODING [EXTRA]
  printf 'NRRD0004\ntype: %s\ndimension: %s\nsizes: %s\nencoding: %s\n' "$2" "$(wc -w <<<"$3")" "$3" "$4" >"$1"
  [[ -z "${5:-}" ]] || printf '%s\n' "$5" >>"$1"
  printf '\n' >>"$1"
  printf '\0\0\0\1\0\0\0\0' >>"$1"
}
case_headers_beyond_their_data_refused_fast() {
nrrd "raw.nrrd" uint8 "100000 100000 100" raw
nrrd "raw16.nrrd" int16 "300 300 300" raw "endian: little"
printf '\0\0\0\1\0\0\0\0\0\0\0\0' | gzip -c >"data.gz"
{ printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 60000 60000 60\nencoding: gzip\n\n'; cat "data.gz"; } >"gzip.nrrd"
for f in raw.nrrd raw16.nrrd gzip.nrrd; do
  refused img2wc "more than the file ([0-9]* bytes) can hold" "$f" "out.nrrd"
  refused wc2implicit "more than the file" "$f" "out.nrrd"
done
# From standard input too (spooled to a file first).
rm -f "out.nrrd"
timeout 20 "$BIN/img2wc" - "out.nrrd" <"raw.nrrd" 2>"err" >/dev/null
rc=$?
[[ $rc == 1 ]] && grep -q '^img2wc: -: .*more than the file' "err" && [[ $(wc -l <"err") == 1 ]] ||
  fail "img2wc on stdin: exit $rc, '$(cat "err")'"
[[ ! -e "out.nrrd" ]] || fail "img2wc on stdin left its output"

# Data in another file: only the machine's memory bounds it (10^12 bytes,
# below the 2^40-voxel limit, above any test machine's memory).
mem=$(awk '/MemTotal/ {printf "%.0f", $2 * 1024}' /proc/meminfo)
if ((mem < 1000000000000)); then
  printf '\0\0\0\0' >"detached.raw"
  printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1000000 1000 1000\nencoding: raw\ndata file: detached.raw\n\n' >"detached.nhdr"
  refused img2wc "declares 1000000000000 bytes of voxels, more than this machine's memory" "detached.nhdr" "out.nrrd"
  refused img2poly "more than this machine's memory" "detached.nhdr" "out.poly"
fi

# MetaImage, NIfTI and PNG headers.
printf 'ObjectType = Image\nNDims = 3\nBinaryData = True\nDimSize = 5000 5000 5000\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n\1\1\1\1' >"big.mha"
refused img2wc "more than the file" "big.mha" "out.nrrd"
python3 - "$PWD" <<'PY'
import struct, sys, zlib
d = sys.argv[1]
h = struct.pack("<i", 348) + b"\0" * 36 + struct.pack("<8h", 3, 10000, 10000, 10000, 1, 1, 1, 1) + b"\0" * 14
h += struct.pack("<hhh", 2, 8, 0) + struct.pack("<8f", 1, 1, 1, 1, 1, 1, 1, 1) + struct.pack("<f", 352.0)
h += b"\0" * (344 - len(h)) + b"n+1\0"
open(d + "/big.nii", "wb").write(h + b"\0" * 4 + b"\1" * 27)
def chunk(t, c):
    return struct.pack(">I", len(c)) + t + c + struct.pack(">I", zlib.crc32(t + c) & 0xffffffff)
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 1000000, 1000000, 8, 0, 0, 0, 0))
open(d + "/big.png", "wb").write(png + chunk(b"IDAT", zlib.compress(b"\0\1\1")) + chunk(b"IEND", b""))
PY
refused img2wc "more than the file" "big.nii" "out.nrrd"
gzip -c "big.nii" >"big.nii.gz"
refused img2wc "more than the file" "big.nii.gz" "out.nrrd"
refused img2poly "more than the file" "big.png" "out.poly"
# Headers libpng refuses come back as one line (ITK alone would abort).
python3 - "$PWD" <<'PY'
import struct, sys, zlib
def chunk(t, c):
    return struct.pack(">I", len(c)) + t + c + struct.pack(">I", zlib.crc32(t + c) & 0xffffffff)
sig = b"\x89PNG\r\n\x1a\n"
open(sys.argv[1] + "/wide.png", "wb").write(sig + chunk(b"IHDR", struct.pack(">IIBBBBB", 1 << 24, 2, 8, 0, 0, 0, 0)))
open(sys.argv[1] + "/depth.png", "wb").write(sig + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 3, 0, 0, 0, 0)))
bad = bytearray(sig + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 0, 0, 0, 0)))
bad[-1] ^= 1
open(sys.argv[1] + "/crc.png", "wb").write(bytes(bad))
PY
for f in wide depth crc; do
  refused img2wc "cannot read the image: " "$f.png" "out.nrrd"
done

# Element counts in the planar and surface readers.
printf 'OFF\n2000000000 2000000000 0\n0 0 0\n3 0 0 0\n' >"counts.off"
printf 'OFF\n9223372036854775807 9223372036854775807 0\n0 0 0\n' >"overflow.off"
for f in counts.off overflow.off; do
  refused tri2quad "truncated" "$f" "out.off"
  refused quadsmooth "truncated" "$f" "out.off"
  refused poly2tri "truncated" "$f" "out.ele"
done
refused meshinfo "truncated" "counts.off"
printf '3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n' >"e.node"
printf '2000000000 3 0\n1 1 2 3\n' >"e.ele"
refused tri2quad "truncated: 2000000000 elements announced" "e.ele" "out.off"
printf '2000000000 2 0 0\n1 0 0\n' >"n.poly"
refused poly2tri "truncated: 2000000000 vertices announced" "n.poly" "out.ele"
}

run_cases "$@"
