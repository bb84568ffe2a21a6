#!/usr/bin/env bash
# ctest commit_msg_hook: scripts/commit-msg accepts readable subjects and refuses the rest.
#   commit_msg_test.sh HOOK
set -uo pipefail
hook=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
failures=0
expect() {  # expect accept|refuse MESSAGE
  printf '%b' "$2" > "$dir/msg"
  if "$hook" "$dir/msg" > /dev/null 2>&1; then got=accept; else got=refuse; fi
  if [ "$got" != "$1" ]; then
    echo "commit_msg_hook: expected $1, got $got: $(head -1 "$dir/msg")" >&2
    failures=$((failures + 1))
  fi
}
expect accept 'Skip the islands phase when nothing can sleep\n'
expect accept 'Feed 16 cores from 4k spheres\n\nThe body holds figures: 1.66 -> 1.02 ms, hash 61f941e.\n'
expect accept '# a comment git strips\nEmbed the settings table in the docs\n'
expect accept "Merge branch 'fix-view'\n"
expect refuse "$(printf 'A%.0s' {1..73})\n"
expect refuse 'Skip the islands phase.\n'
expect refuse 'Skipped the islands phase\n'
expect refuse 'Fixing the islands phase\n'
expect refuse 'skip the islands phase\n'
expect refuse 'Skip the islands phase\nwith no blank line before the body\n'
expect refuse '\n\n'
[ "$failures" -eq 0 ] && echo "commit_msg_hook: ok"
exit "$failures"
