#!/usr/bin/env bash
# The plugin ABI as the linker sees it (docs/writing-a-plugin.md, "What a plugin may use").
#   check_plugin_abi.sh LIBNOETHER_CORE PLUGIN.so...
# Lists the noether symbols libnoether-core exports (its versioned interface: whatever its
# headers declare), then fails if a plugin
#   - needs a noether library other than libnoether-core (the host or the orbits library), or
#   - links a noether symbol that libnoether-core does not export, or
#   - leaves any symbol unresolved by the libraries it links (`ldd -r`): a plugin that relies on
#     the process having loaded a library (the driver links spdlog and fmt; Python does not) loads
#     in `noether` and fails in `import noether`.
set -euo pipefail
core=$1
shift
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
noether_symbols() { grep -E '^(noether::|typeinfo for noether::|typeinfo name for noether::|vtable for noether::)' || true; }
nm -DC --defined-only "$core" | cut -c 20- | noether_symbols | sort -u > "$work/exports"
echo "libnoether-core exports $(wc -l < "$work/exports") noether symbols:"
sed 's/^/  /' "$work/exports"
status=0
for plugin in "$@"; do
  name=$(basename "$plugin")
  needed=$(readelf -d "$plugin" | sed -n 's/.*Shared library: \[\(libnoether[^]]*\)\].*/\1/p')
  for lib in $needed; do
    case $lib in
      libnoether-core.so*) ;;
      *) echo "FAIL $name needs $lib: plugins may link libnoether-core only"; status=1 ;;
    esac
  done
  # (A sanitizer build's runtime symbols come from the executable, by design: not counted.)
  unresolved=$(ldd -r "$plugin" 2>&1 | grep "undefined symbol" | grep -Ev "undefined symbol: __(asan|ubsan|sancov|sanitizer|lsan)" || true)
  if [ -n "$unresolved" ]; then
    echo "FAIL $name leaves symbols unresolved by its own libraries (link them):"
    echo "$unresolved" | head -3 | sed 's/^/  /'
    status=1
  fi
  nm -DC --undefined-only "$plugin" | sed 's/^ *U //' | noether_symbols | sort -u > "$work/uses"
  outside=$(comm -23 "$work/uses" "$work/exports")
  if [ -n "$outside" ]; then
    echo "FAIL $name links noether symbols outside libnoether-core's interface:"
    echo "$outside" | sed 's/^/  /'
    status=1
  else
    echo "ok   $name: $(wc -l < "$work/uses") noether symbols, all from libnoether-core"
  fi
done
exit $status
