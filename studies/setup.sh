#!/usr/bin/env bash
# Set up what mpm1d needs, installing only what is missing and leaving the system's Python alone:
#   - apt packages (the system's to have, installed when missing, never upgraded): gfortran,
#     libhdf5-dev, hdf5-tools, pkg-config, python3-venv, python3-numpy,
#     python3-matplotlib, python3-h5py, python3-pytest, python3-pandas;
#   - the project's own virtual environment .venv at the top of this checkout, made by Debian's
#     interpreter: `/usr/bin/python3 -m venv --system-site-packages .venv` (numpy, h5py, matplotlib,
#     pytest and pandas come from apt through it), holding fpm, fypp and ford from PyPI, nbclient and
#     ipykernel from PyPI (what executes the tutorial notebook; versions below) and this checkout's
#     post-processing package (postprocess/, editable: `mpm1d-plot-sweep` & co.).
# Nothing goes into the system interpreter, pyenv or ~/.local, and no other checkout's install is
# touched: two clones have two venvs. The `python3` on PATH (pyenv or other) is not used.
# Run it (`bash studies/setup.sh`) or source it (`source studies/setup.sh`, as every script here
# does) to get PYTHON=<checkout>/.venv/bin/python and <checkout>/.venv/bin first on PATH (the
# venv's fpm), and the study scripts' build function mpm1d_build (below).
_mpm1d_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
_mpm1d_venv="$_mpm1d_root/.venv"
# the PyPI tools, pinned: fpm 0.12 is the version whose (re)linking the test runner works with
_mpm1d_tools="fpm==0.12.0 fypp==3.3 ford==7.0.13"
# what executes docs/tutorial.ipynb (nbclient, on an ipykernel of this venv), pinned: IPython and
# matplotlib-inline as Debian 12's matplotlib 3.6 needs them (IPython 9 and matplotlib-inline 0.2 call
# matplotlib >= 3.7, and %matplotlib inline fails)
_mpm1d_notebook="nbclient==0.10.2 ipykernel==6.29.5 ipython==8.18.1 matplotlib-inline==0.1.6"
_mpm1d_apt="gfortran libhdf5-dev hdf5-tools pkg-config python3-venv python3-numpy
  python3-matplotlib python3-h5py python3-pytest python3-pandas"

_mpm1d_setup() {
  local missing="" p sudo=""
  # apt: only the packages that are not installed
  if command -v dpkg-query >/dev/null 2>&1; then
    for p in $_mpm1d_apt; do
      dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing="$missing $p"
    done
  fi
  if [ -n "$missing" ]; then
    if [ "$(id -u)" != 0 ]; then
      if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then sudo="sudo"
      else echo "setup: missing apt packages:$missing; install them with: sudo apt-get install$missing" >&2; return 1; fi
    fi
    echo "setup: installing (apt):$missing" >&2
    $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq $missing >/dev/null \
      || { echo "setup: apt-get install$missing failed" >&2; return 1; }
  fi

  # the project's virtual environment, by Debian's interpreter, seeing apt's numpy, h5py, matplotlib, pytest
  if [ ! -e "$_mpm1d_venv/bin/python" ]; then
    echo "setup: making the project's virtual environment: /usr/bin/python3 -m venv --system-site-packages .venv" >&2
    /usr/bin/python3 -m venv --system-site-packages "$_mpm1d_venv" \
      || { echo "setup: could not make $_mpm1d_venv" >&2; return 1; }
  fi
  if ! "$_mpm1d_venv/bin/python" -I -c 'import numpy, h5py, matplotlib, pytest, pandas' >/dev/null 2>&1; then
    echo "setup: $_mpm1d_venv/bin/python does not import numpy, h5py, matplotlib, pytest and pandas (apt's);" \
         "was .venv made otherwise? Remove it and run studies/setup.sh again" >&2
    return 1
  fi

  # fpm, fypp, ford from PyPI into the venv (the stamp names the versions installed)
  if [ "$(cat "$_mpm1d_venv/.mpm1d-tools" 2>/dev/null)" != "$_mpm1d_tools" ] || [ ! -x "$_mpm1d_venv/bin/fpm" ] \
     || [ ! -x "$_mpm1d_venv/bin/fypp" ] || [ ! -x "$_mpm1d_venv/bin/ford" ]; then
    echo "setup: installing $_mpm1d_tools into .venv (pip of the venv)" >&2
    # shellcheck disable=SC2086
    "$_mpm1d_venv/bin/python" -m pip install -q $_mpm1d_tools >&2 \
      || { echo "setup: pip install $_mpm1d_tools into .venv failed" >&2; return 1; }
    echo "$_mpm1d_tools" > "$_mpm1d_venv/.mpm1d-tools"
  fi
  if [ "$(cat "$_mpm1d_venv/.mpm1d-notebook" 2>/dev/null)" != "$_mpm1d_notebook" ]; then
    echo "setup: installing $_mpm1d_notebook into .venv (pip of the venv)" >&2
    # shellcheck disable=SC2086
    "$_mpm1d_venv/bin/python" -m pip install -q $_mpm1d_notebook >&2 \
      || { echo "setup: pip install $_mpm1d_notebook into .venv failed" >&2; return 1; }
    echo "$_mpm1d_notebook" > "$_mpm1d_venv/.mpm1d-notebook"
  fi

  # this checkout's post-processing package, editable, unless the venv already imports it from here and
  # was installed from the pyproject.toml of now (its console scripts are made at install: the stamp
  # holds the file's checksum)
  local stamp
  stamp="$(cksum < "$_mpm1d_root/postprocess/pyproject.toml")"
  if [ "$(cat "$_mpm1d_venv/.mpm1d-post" 2>/dev/null)" != "$stamp" ] \
     || ! (cd / && "$_mpm1d_venv/bin/python" -I - "$_mpm1d_root/postprocess" >/dev/null 2>&1) <<'PY'
import pathlib, sys
import mpm1d_post
sys.exit(pathlib.Path(mpm1d_post.__file__).resolve().parents[1] != pathlib.Path(sys.argv[1]).resolve())
PY
  then
    echo "setup: installing the post-processing package into .venv (pip install -e postprocess)" >&2
    "$_mpm1d_venv/bin/python" -m pip install -q --no-deps --no-build-isolation -e "$_mpm1d_root/postprocess" >&2 \
      || { echo "setup: the post-processing package could not be installed into .venv" >&2; return 1; }
    echo "$stamp" > "$_mpm1d_venv/.mpm1d-post"
  fi
}

if ! _mpm1d_setup; then
  unset -f _mpm1d_setup
  return 1 2>/dev/null || exit 1
fi
unset -f _mpm1d_setup
if [ -n "${PYTHON:-}" ] && [ "$PYTHON" != "$_mpm1d_venv/bin/python" ]; then
  echo "setup: PYTHON=$PYTHON replaced by the project's $_mpm1d_venv/bin/python" >&2
fi
export PYTHON="$_mpm1d_venv/bin/python"
export PATH="$_mpm1d_venv/bin:$PATH"
hash -r

# Build of the study scripts (local runs): for this machine's CPU (-march=native, about twice the
# kernels' speed) unless PORTABLE=1 (fpm's plain release profile, the build the tests and the SLURM
# scripts use); FLAGS, if set, replaces -march=native. `mpm1d_build` builds and prints the path of the
# mpm1d executable of that build; `mpm1d_build --example mpm1d_bench` that of the benchmark.
# A build with FLAGS takes fpm 0.12's release flags for gfortran without -funroll-loops (fpm puts its
# profile's flags after --flag's, so -fno-unroll-loops cannot undo them): unrolled, the vector loops of
# -march=native (with their remainder loops) made the code of one step of a small run (the paper's
# Table 2: 1-50 elements) too large for the level-1 instruction cache (USF sweep: 19.5e6 misses
# against 9.4e6 without unrolling); large runs gain nothing from it (docs/performance.md, "The Table-2
# error pass on the native build").
# On the Intel CPUs that Gather Data Sampling affects (Skylake to Ice Lake, Tiger Lake and Rocket Lake),
# the native build also asks for no gather instructions (vgatherdpd: a vector load from a vector of
# indices, which the kernels' loops use for the grid values at each particle's cell): Intel's microcode
# against it (2023) made them several times slower there, and later GCC releases no longer emit them when
# tuning for these CPUs; Debian 12's gfortran 12.2 still does. The option is -mno-gather where gfortran
# takes it, else gfortran 12's tuning switches. On an Ice Lake server, with gathers, the paper's Table-2
# sweeps took 1.8x as long, and one-thread steps 2.2-2.5x as long at 1e3-1e5 particles and 1.45x at
# 1e6; the results are bit for bit the same (docs/performance.md, "Gather instructions"). Other CPUs keep
# them; FLAGS=-march=native keeps them everywhere.
mpm1d_no_gather_flag() {
  local dir option arch
  arch="$(gfortran -march=native -Q --help=target 2>/dev/null | awk '$1 == "-march=" {print $2; exit}')"
  case "$arch" in
    skylake|skylake-avx512|cascadelake|cooperlake|cannonlake|icelake-client|icelake-server|tigerlake|rocketlake) ;;
    *) return 0 ;;
  esac
  dir="$(mktemp -d)" || return 0
  printf 'end\n' > "$dir/probe.f90"
  for option in -mno-gather "-mtune-ctrl=^use_gather_2parts,^use_gather_4parts,^use_gather"; do
    if gfortran -march=native "$option" -c "$dir/probe.f90" -o "$dir/probe.o" >/dev/null 2>&1; then
      echo "$option"
      break
    fi
  done
  rm -rf "$dir"
}
if [ -z "${FLAGS+x}" ]; then
  if [ "${PORTABLE:-0}" = 1 ]; then FLAGS=""; else
    FLAGS="-march=native"
    _mpm1d_gather="$(mpm1d_no_gather_flag)"
    [ -n "$_mpm1d_gather" ] && FLAGS="$FLAGS $_mpm1d_gather"
  fi
fi
MPM1D_RELEASE_FLAGS="-O3 -Wimplicit-interface -fPIC -fmax-errors=1 -fcoarray=single"
# the fpm options of the build that FLAGS selects (in the array mpm1d_fpm_options)
mpm1d_build_options() {
  if [ -z "$FLAGS" ]; then mpm1d_fpm_options=(--profile release)
  else mpm1d_fpm_options=(--flag "$MPM1D_RELEASE_FLAGS $FLAGS"); fi
}
mpm1d_build() {
  local target=(--target mpm1d) mpm1d_fpm_options
  [ "$#" -gt 0 ] && target=("$@")
  mpm1d_build_options
  fpm build "${mpm1d_fpm_options[@]}" >/dev/null || return 1
  echo "$PWD/$(fpm run "${mpm1d_fpm_options[@]}" "${target[@]}" --runner echo 2>/dev/null | tail -n 1)"
}
