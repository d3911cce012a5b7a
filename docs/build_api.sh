#!/usr/bin/env bash
# API documentation from the `!>` comments of src/ and app/, by FORD (PyPI `ford`), into build/ford/
# (git-ignored; open build/ford/index.html). Settings: docs/ford.md.
#
#   bash docs/build_api.sh
#
# Exit status 0 when FORD built the pages without a single warning; 1 when it printed any warning
# (listed; the pages are still written), so that CI can run this line as its check; 2 when FORD is
# missing or failed. FORD comes from the project venv: .venv/bin/pip install ford (or
# FORD=/path/to/ford). The version shown is fpm.toml's.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
ford="${FORD:-$root/.venv/bin/ford}"
if ! [ -x "$ford" ] && ! command -v "$ford" > /dev/null 2>&1; then
   echo "build_api.sh: FORD not found at $ford; install it into the project venv: .venv/bin/pip install ford" >&2
   exit 2
fi
version="$(sed -n 's/^version *= *"\(.*\)"/\1/p' fpm.toml | head -n 1)"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
# COLUMNS: one warning per line (rich wraps at the terminal's width); NO_COLOR: plain text to grep.
if ! COLUMNS=1000 NO_COLOR=1 "$ford" --revision "$version" docs/ford.md > "$log" 2>&1; then
   cat "$log" >&2
   echo "build_api.sh: FORD failed" >&2
   exit 2
fi
warnings="$(grep -c 'Warning:' "$log" || true)"
size="$(du -sh build/ford | cut -f1)"
files="$(find build/ford -type f | wc -l)"
if [ "$warnings" -gt 0 ]; then
   grep 'Warning:' "$log" >&2
   echo "build_api.sh: FORD printed $warnings warning(s) (pages in build/ford, $size); fix the \`!>\` comments or docs/ford.md" >&2
   exit 1
fi
echo "build_api.sh: build/ford/index.html written ($files files, $size), 0 warnings"
