# Images the project does not bundle, from Debian's own packages (so a bench
# can measure on images the project has not been tuned on): sourced by the
# bench scripts. debian_file PKG PATH prints the local path of PATH inside
# package PKG (fetched once with apt-get download into $IMGMESH_CACHE);
# PATH may go on inside a tarball of the package: "a/b.tar.gz//c/d".
IMGMESH_CACHE=${IMGMESH_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/imgmesh}
debian_file() {
  local pkg=$1 path=$2 dir="$IMGMESH_CACHE/$1"
  if [[ ! -d $dir ]]; then
    mkdir -p "$IMGMESH_CACHE"
    local tmp
    tmp=$(mktemp -d "$IMGMESH_CACHE/.fetch.XXXXXX")
    (cd "$tmp" && apt-get download "$pkg" >/dev/null 2>&1 && dpkg-deb -x ./*.deb x) ||
      { rm -rf "$tmp"; echo "debian_data: cannot fetch package $pkg" >&2; return 1; }
    mv "$tmp/x" "$dir" && rm -rf "$tmp"
  fi
  if [[ $path == *//* ]]; then
    local tarball=$dir/${path%%//*} inner=${path#*//}
    [[ -f $dir/untar/$inner ]] || { mkdir -p "$dir/untar" && tar -xzf "$tarball" -C "$dir/untar" "$inner"; }
    echo "$dir/untar/$inner"
  else
    echo "$dir/$path"
  fi
}

# unseen_image NAME OUT: the well-composed image of one of the unseen cases,
# written to OUT by img2wc ($tools must be set). Returns 1 for other names.
#   t1-60, t1-100: ITK's raw T1 head MR (128x128x62, 2x2x3 mm) thresholded at
#     grey 60 and 100 (noisy tissue, hundreds of components);
#   t1-mask: the brain mask (label 6) of ITK's skull-stripping example;
#   ct-skull: CGAL's skull CT (64^3 float, 3.9 mm) at its example's iso 2.9.
unseen_image() {
  local itk=usr/share/doc/insighttoolkit5-examples/examples/Data
  case $1 in
    t1-60|t1-100)
      "$tools/img2wc" -q "$(debian_file insighttoolkit5-examples $itk/KmeansTest_T1UCharRaw.nii.gz)" \
        --threshold "${1#t1-}" "$2" ;;
    t1-mask)
      "$tools/img2wc" -q "$(debian_file insighttoolkit5-examples $itk/KmeansTest_T1RawSkullStrip.nii.gz)" \
        --label 6 "$2" ;;
    ct-skull)
      local inr
      inr=$(debian_file libcgal-demo usr/share/doc/libcgal-dev/data.tar.gz//data/images/skull_2.9.inr)
      # MetaImage header over the INRIMAGE file (256-byte header, little-endian float).
      printf '%s\n' "ObjectType = Image" "NDims = 3" "DimSize = 64 64 64" \
        "ElementSpacing = 3.94305 3.94305 3.65079" "ElementType = MET_FLOAT" "BinaryData = True" \
        "BinaryDataByteOrderMSB = False" "HeaderSize = 256" "ElementDataFile = $inr" > "${2%.*}-skull.mhd"
      "$tools/img2wc" -q "${2%.*}-skull.mhd" --threshold 2.9 "$2" ;;
    *) return 1 ;;
  esac
}
