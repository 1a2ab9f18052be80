#!/usr/bin/env bash
# Fetches the map's source data from the npm registry, checks it against the checksums below and unpacks
# countries-50m.json (world-atlas, Natural Earth) and counties-10m.json (us-atlas, U.S. Census) into DEST.
# Usage: tools/fetch-map-data.sh DEST. Exits non-zero (DEST left without the files) when a fetch or check fails.
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 DEST" >&2; exit 2; }
dest=$1
mkdir -p "$dest"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# name version sha512 (npm's dist.integrity) sha1 (npm's dist.shasum) file-in-package
packages=(
  "world-atlas 2.0.2 IXfV0qwlKXpckz1FhwXVwKRjiIhOnWttOskm5CtxMsjgE/MXAYRHWJqgXOpM8IkcPBoXnyTU5lFHcYa5ChG0LQ== 4bca4a578f3a413bd409c3f07f2054fe7375824f countries-50m.json"
  "us-atlas 3.0.1 wEIZCq0ImPvGblTd8gZMqNNCPkQshugMUG/8nkSWXb02+XqNFREg9atHOKP9w6prLZTpqcLhSvdBW81MkV3/0Q== 367d64e4b31d3f945827710f1a43813c38e17d6b counties-10m.json"
)

fetch() {  # name version -> $work/name-version.tgz, by npm when present, else the registry's tarball URL
    local name=$1 version=$2 tgz="$work/$1-$2.tgz"
    if command -v npm >/dev/null 2>&1 && (cd "$work" && npm pack --silent "$name@$version" >/dev/null 2>&1) \
        && [ -f "$tgz" ]; then
        return 0
    fi
    local url="https://registry.npmjs.org/$name/-/$name-$version.tgz"
    if command -v curl >/dev/null 2>&1; then
        curl -fsSL --retry 2 -o "$tgz" "$url"
    else
        wget -q -O "$tgz" "$url"
    fi
}

for entry in "${packages[@]}"; do
    read -r name version sha512 sha1 file <<<"$entry"
    if [ -f "$dest/$file" ] && [ -f "$dest/.$file.sha1" ] && [ "$(cat "$dest/.$file.sha1")" = "$sha1" ]; then
        echo "fetch-map-data: $file present ($name@$version)"
        continue
    fi
    fetch "$name" "$version" || { echo "fetch-map-data: cannot fetch $name@$version" >&2; exit 1; }
    tgz="$work/$name-$version.tgz"
    # npm's integrity is base64; compared in hex with coreutils alone.
    want512=$(printf '%s' "$sha512" | base64 -d | od -An -v -tx1 | tr -d ' \n')
    got512=$(sha512sum "$tgz" | cut -d' ' -f1)
    got1=$(sha1sum "$tgz" | cut -d' ' -f1)
    if [ "$got512" != "$want512" ] || [ "$got1" != "$sha1" ]; then
        echo "fetch-map-data: checksum mismatch for $name@$version (sha512 $got512, sha1 $got1)" >&2
        exit 1
    fi
    tar -xzf "$tgz" -C "$work" "package/$file"
    mv "$work/package/$file" "$dest/$file"
    echo "$sha1" >"$dest/.$file.sha1"
    echo "fetch-map-data: $file from $name@$version (checksums match)"
done
