#!/usr/bin/env bash
# Places the XML schemas that the tests validate Gonio's output against in
# ../shared/schemas beside the checkout (never committed: other projects'
# files). Idempotent; tests that need a schema missing here skip, and fail
# under CI=true (GONIO_MISSING).
#
#   l3d.xsd  the L3D structure.xml schema as the GLDF project publishes it
#            (github.com/globallightingdata/l3d, xsd/l3d.xsd), which Gonio's
#            written structure.xml names (https://gldf.io/xsd/l3d/l3d.xsd).
#
# Source, first found: $GONIO_L3D_REPO (a clone, or a bare mirror, of
# globallightingdata/l3d), else a download from GitHub (curl).
#
# (gldf-1.0.0-rc.3.xsd, the product.xml schema, is placed the same way from
# holg/gldf-rs, tests/data/gldf-1.0.0-rc-3.xsd, where $GONIO_GLDF_RS_REPO
# names a clone or mirror.)
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
dest="${GONIO_SCHEMAS_DIR:-$root/../shared/schemas}"
mkdir -p "$dest"

# place NAME REPO_ENV PATH_IN_REPO URL
place() {
  local name="$1" repo="$2" path="$3" url="$4" tmp
  if [ -s "$dest/$name" ]; then
    echo "place-schemas: $dest/$name is there"
    return 0
  fi
  tmp="$(mktemp "$dest/.$name.XXXXXX")"
  chmod 644 "$tmp"
  if [ -n "$repo" ] && [ -f "$repo/$path" ]; then
    cp "$repo/$path" "$tmp"
  elif [ -n "$repo" ] && git -C "$repo" rev-parse --git-dir > /dev/null 2>&1; then
    git -C "$repo" show "HEAD:$path" > "$tmp"
  elif command -v curl > /dev/null; then
    if ! curl -fsSL "$url" -o "$tmp"; then
      rm -f "$tmp"
      echo "place-schemas: could not download $url" >&2
      return 1
    fi
  else
    rm -f "$tmp"
    echo "place-schemas: no source for $name (set the repository's variable, or install curl)" >&2
    return 1
  fi
  if ! grep -q "<xs:schema" "$tmp"; then
    rm -f "$tmp"
    echo "place-schemas: what was found for $name is no XML schema" >&2
    return 1
  fi
  mv "$tmp" "$dest/$name"
  echo "place-schemas: placed $dest/$name"
}

status=0
place l3d.xsd "${GONIO_L3D_REPO:-}" xsd/l3d.xsd \
  https://raw.githubusercontent.com/globallightingdata/l3d/master/xsd/l3d.xsd || status=1
place gldf-1.0.0-rc.3.xsd "${GONIO_GLDF_RS_REPO:-}" tests/data/gldf-1.0.0-rc-3.xsd \
  https://raw.githubusercontent.com/holg/gldf-rs/main/tests/data/gldf-1.0.0-rc-3.xsd || status=1
exit "$status"
