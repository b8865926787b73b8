#!/usr/bin/env bash
# check_runpath.sh FILE...: every RUNPATH/RPATH entry of every ELF file is absolute or starts
# with $ORIGIN. An empty entry (a leading, trailing or doubled ':') or a relative one is the
# working directory: a library planted there would be loaded by `noether --version`.
status=0
bad() { echo "check_runpath: $1: RUNPATH [$2] $3"; status=1; }
for f in "$@"; do
  path=$(readelf -d "$f" | sed -n 's/.*(\(RUNPATH\|RPATH\)).*\[\(.*\)\]/\2/p')
  [ -z "$path" ] && { echo "$f: no RUNPATH"; continue; }
  case "$path" in :*|*:|*::*) bad "$f" "$path" "has an empty entry (the working directory)"; continue ;; esac
  IFS=':' read -r -a entries <<<"$path"
  for e in "${entries[@]}"; do
    case "$e" in /*|'$ORIGIN'|'$ORIGIN'/*) ;; *) bad "$f" "$path" "has the relative entry '$e'" ;; esac
  done
  echo "$f: RUNPATH [$path]"
done
exit $status
