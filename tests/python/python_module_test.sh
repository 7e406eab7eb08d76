#!/usr/bin/env bash
# Installs this build into a temporary prefix (cmake --install, as `make install` does), then runs
# python_module_check.py in Debian's python3 with only that prefix's site-packages added, so the
# module under test is the installed one. Usage:
#   python_module_test.sh BUILD_DIR NEPHELE_GEN PYTHON CHECK_SCRIPT WORKDIR
set -euo pipefail
build=$1 gen=$2 python=$3 check=$4 work=$5
rm -rf "$work" && mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
site="$work/prefix/lib/python3/dist-packages"
[ -f "$site/nephele/__init__.py" ] || { echo "make install put no nephele package into $site:"; find "$work/prefix" -path '*nephele*' -name '*.py'; exit 1; }
ls "$site"/nephele/_nephele*.so > /dev/null
PYTHONPATH="$site" "$python" "$check" "$work/prefix/bin/nephele" "$gen" "$site" "$work"
