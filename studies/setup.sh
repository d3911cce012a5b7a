#!/usr/bin/env bash
# Install what mpm1d needs and is missing: gfortran, HDF5 (library, Fortran modules, tools),
# fpm (from PyPI), numpy/matplotlib/h5py/pytest for the Python interpreter the scripts use, and the
# post-processing package of this checkout (postprocess/, `pip install -e`, editable).
# Safe to run again: it installs only what is missing. Source it to get $PYTHON and fpm on PATH:
#   source studies/setup.sh
# The Python used is $PYTHON if set, else Debian's /usr/bin/python3 (packages from apt);
# any other interpreter gets numpy/matplotlib/h5py/pytest from pip.
set -e
_sudo=""
if [ "$(id -u)" != 0 ] && command -v sudo >/dev/null 2>&1; then _sudo="sudo"; fi
_apt_updated=0
_apt_install() {
  if [ "$_apt_updated" = 0 ]; then $_sudo apt-get update -qq; _apt_updated=1; fi
  DEBIAN_FRONTEND=noninteractive $_sudo apt-get install -y -qq "$@" >/dev/null
}

if ! command -v gfortran >/dev/null 2>&1 || ! command -v h5dump >/dev/null 2>&1 \
   || ! command -v pkg-config >/dev/null 2>&1 || ! pkg-config --exists hdf5 2>/dev/null; then
  echo "setup: installing gfortran, libhdf5-dev, hdf5-tools (apt)" >&2
  _apt_install gfortran libhdf5-dev hdf5-tools pkg-config
fi

PYTHON="${PYTHON:-/usr/bin/python3}"
if [ ! -x "$PYTHON" ]; then
  echo "setup: installing python3 (apt)" >&2
  _apt_install python3
fi
if ! "$PYTHON" -c "import numpy, matplotlib, h5py, pytest" >/dev/null 2>&1 \
   || ! "$PYTHON" -m pip --version >/dev/null 2>&1; then
  if [ "$PYTHON" = /usr/bin/python3 ]; then
    echo "setup: installing python3-numpy python3-matplotlib python3-h5py python3-pytest python3-pip (apt)" >&2
    _apt_install python3-numpy python3-matplotlib python3-h5py python3-pytest python3-pip python3-setuptools
  else
    echo "setup: installing numpy matplotlib h5py pytest for $PYTHON (pip)" >&2
    "$PYTHON" -m pip install -q numpy matplotlib h5py pytest
  fi
fi
export PYTHON

# The post-processing package (postprocess/: the loader, figures, plotting commands), installed
# editable from this checkout unless $PYTHON already imports it from here. Debian's interpreter is
# "externally managed": pip needs --break-system-packages (as root it installs into /usr/local,
# otherwise into ~/.local), and uses apt's setuptools (no download).
_mpm1d_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if ! "$PYTHON" - "$_mpm1d_root/postprocess" >/dev/null 2>&1 <<'PY'
import pathlib, sys
import mpm1d_post
sys.exit(pathlib.Path(mpm1d_post.__file__).resolve().parents[1] != pathlib.Path(sys.argv[1]).resolve())
PY
then
  echo "setup: installing the post-processing package (pip install -e postprocess)" >&2
  _pip=("$PYTHON" -m pip install -q --no-deps)
  if [ "$PYTHON" = /usr/bin/python3 ]; then _pip+=(--no-build-isolation); fi
  if "$PYTHON" -c "import os, sys, sysconfig; sys.exit(not os.path.exists(os.path.join(sysconfig.get_path('stdlib'), 'EXTERNALLY-MANAGED')))"; then
    _pip+=(--break-system-packages)
  fi
  "${_pip[@]}" -e "$_mpm1d_root/postprocess" >&2 \
    || { echo "setup: the post-processing package could not be installed" >&2; return 1 2>/dev/null || exit 1; }
fi
# its commands (mpm1d-plot-sweep, ...): pip puts them in the interpreter's or the user's scripts folder
for _scripts in "$("$PYTHON" -c 'import sysconfig; print(sysconfig.get_path("scripts"))')" "$HOME/.local/bin"; do
  case ":$PATH:" in *":$_scripts:"*) ;; *) [ -d "$_scripts" ] && PATH="$PATH:$_scripts" ;; esac
done
export PATH

if ! command -v fpm >/dev/null 2>&1; then
  echo "setup: installing fpm (pip)" >&2
  if command -v pip >/dev/null 2>&1 && pip install -q fpm 2>/dev/null; then :
  elif ! command -v pip >/dev/null 2>&1 && ! /usr/bin/python3 -m pip --version >/dev/null 2>&1; then
    _apt_install python3-pip
  fi
  if ! command -v fpm >/dev/null 2>&1; then
    /usr/bin/python3 -m pip install -q --user --break-system-packages fpm 2>/dev/null \
      || /usr/bin/python3 -m pip install -q --user fpm
    export PATH="$HOME/.local/bin:$PATH"
  fi
  hash -r
fi
command -v fpm >/dev/null 2>&1 || { echo "setup: fpm could not be installed" >&2; exit 1; }
set +e

# Build of the study scripts (local runs): for this machine's CPU (-march=native, about twice the
# kernels' speed) unless PORTABLE=1 (fpm's plain release profile, the build the tests and the SLURM
# scripts use); FLAGS, if set, is passed to fpm as it is. `mpm1d_build` builds and prints the path of
# the mpm1d executable of that build; `mpm1d_build --example mpm1d_bench` that of the benchmark.
if [ -z "${FLAGS+x}" ]; then
  if [ "${PORTABLE:-0}" = 1 ]; then FLAGS=""; else FLAGS="-march=native"; fi
fi
mpm1d_build() {
  local target=(--target mpm1d)
  [ "$#" -gt 0 ] && target=("$@")
  fpm build --profile release --flag "$FLAGS" >/dev/null || return 1
  echo "$PWD/$(fpm run --profile release --flag "$FLAGS" "${target[@]}" --runner echo 2>/dev/null | tail -n 1)"
}
