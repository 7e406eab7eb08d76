#!/usr/bin/env bash
# Every C/C++ file of the tree is in the .clang-format style (issue 17): clang-format --dry-run
# --Werror names each file and line that would change. usage: clang_format_check.sh CLANG_FORMAT SRC
set -euo pipefail
clang_format=$1 src=$2
cd "$src"
list=$(mktemp)
trap 'rm -f "$list"' EXIT
if git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  git ls-files -z '*.h' '*.cpp' '*.c' > "$list"
else  # a source tree without git (a tarball): the same folders
  find src tests plugins examples data_tools include -type f \( -name '*.h' -o -name '*.cpp' -o -name '*.c' \) \
       -print0 > "$list"
fi
count=$(tr -cd '\0' < "$list" | wc -c)
xargs -0 "$clang_format" --dry-run --Werror < "$list"
echo "clang-format: $count files in the .clang-format style"
