#!/usr/bin/env bash
# plugin_files.sh NOETHER PLUGIN.so WORK_DIR: a plugin file that would crash dlopen (truncated)
# or that anyone could replace (writable by others) is refused by name before it is loaded.
set -u
noether=$1; plugin=$2; work=$3
fail() { echo "plugin_files: FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && chmod 755 "$work" || exit 1
scene=$(dirname "$0")/../../examples/dumbbells.yaml
head -c $(( $(stat -c %s "$plugin") / 2 )) "$plugin" > "$work/noether-trunc.so"
out=$(NOETHER_PLUGIN_PATH=$work "$noether" run "$scene" --no-progress --set potential.plugin=trunc 2>&1); rc=$?
[ $rc -eq 2 ] || fail "truncated: exit $rc (a crash is 135), expected 2: $out"
grep -q "is not loaded: it is truncated" <<<"$out" || fail "truncated: $out"
rm "$work/noether-trunc.so"
cp "$plugin" "$work/noether-open.so" && chmod 666 "$work/noether-open.so"
out=$(NOETHER_PLUGIN_PATH=$work "$noether" run "$scene" --no-progress --set potential.plugin=open 2>&1); rc=$?
[ $rc -eq 2 ] || fail "world-writable: exit $rc, expected 2: $out"
grep -q "is not loaded: it is writable by every user" <<<"$out" || fail "world-writable: $out"
echo "plugin_files: all checks passed"
