#!/usr/bin/env bash
# Lists every C++ file of the project that is not clean under the repository's .clang-format with
# Debian's clang-format-14 (scripts/install-deps.sh installs it) and fails if there is one.
# Usage: scripts/check-format.sh [--fix]     (--fix: reformat them in place)
set -euo pipefail
cd "$(dirname "$0")/.."
CLANG_FORMAT=${CLANG_FORMAT:-clang-format-14}
if ! command -v "$CLANG_FORMAT" >/dev/null 2>&1; then
  echo "check-format: $CLANG_FORMAT not found (scripts/install-deps.sh installs it)" >&2
  exit 2
fi
mapfile -t files < <(git ls-files --cached --others --exclude-standard -- \
  'src/*.cc' 'src/*.h' 'app/*.cc' 'app/*.h' 'bench/*.cc' 'bench/*.h' 'tests/*.cc' 'tests/*.h' \
  'tools/*.cc' 'tools/*.h' 'examples/*.cc' 'examples/*.h' 'ros/*.cc' 'ros/*.h' 'ros2/*.cc' 'ros2/*.h' 'python/*.cc' 'python/*.h')
unclean=()
for f in "${files[@]}"; do
  [ -f "$f" ] || continue
  if ! "$CLANG_FORMAT" --dry-run --Werror "$f" >/dev/null 2>&1; then unclean+=("$f"); fi
done
if [ "${1:-}" = "--fix" ] && [ ${#unclean[@]} -gt 0 ]; then
  "$CLANG_FORMAT" -i "${unclean[@]}"
  echo "check-format: reformatted ${#unclean[@]} file(s)"
  exit 0
fi
if [ ${#unclean[@]} -gt 0 ]; then
  echo "check-format: ${#unclean[@]} of ${#files[@]} C++ files are not clean under .clang-format ($CLANG_FORMAT):" >&2
  printf '  %s\n' "${unclean[@]}" >&2
  echo "fix with: scripts/check-format.sh --fix" >&2
  exit 1
fi
echo "check-format: all ${#files[@]} C++ files clean under .clang-format"
