#!/usr/bin/env bash
# expect.sh CODE REGEX COMMAND...: runs COMMAND, passes if it exits with CODE and its
# combined output matches the extended regular expression REGEX.
code=$1; regex=$2; shift 2
out=$("$@" 2>&1); rc=$?
printf '%s\n' "$out"
if [ "$rc" -ne "$code" ]; then echo "expect.sh: exit code $rc, expected $code"; exit 1; fi
if ! printf '%s\n' "$out" | tr '\n' ' ' | grep -Eq -- "$regex"; then
  echo "expect.sh: output does not match: $regex"; exit 1
fi
