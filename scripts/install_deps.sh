#!/usr/bin/env bash
# Installs, with apt-get, whichever of clothsim's Debian 12 packages are missing (nothing else).
# Run as root (or with sudo available). A second call finds everything installed and returns at once.
#
#   bash scripts/install_deps.sh
#
# Packages (checked with Debian 12's PETSc 3.18.5, Open MPI 4.1.4, HDF5 1.10.8, METIS 5.1.0, CMake 3.25.1, GCC 12.2):
#   build:        gcc libc6-dev make cmake pkg-config
#   style:        clang-format   (14 on Debian 12; the ctest style_clang_format checks src/ against .clang-format)
#   libraries:    petsc-dev libopenmpi-dev openmpi-bin libhdf5-openmpi-dev libmetis-dev libyaml-dev
#                 libopenblas0-serial   (an optimised BLAS/LAPACK in place of the reference one, through Debian's
#                 alternatives: MUMPS's Cholesky factorisation, which the fine-grid drape study uses, runs
#                 4-5 times faster with it; serial, so that MPI ranks do not start BLAS threads on top)
#   postprocess:  hdf5-tools python3-h5py python3-matplotlib python3-numpy python3-ezdxf
#   ParaView:     paraview python3-paraview xvfb xauth   (pvpython reads the XDMF output; xvfb-run renders)
#   movies:       ffmpeg   (postprocess/movie.py encodes the rendered frames into MP4; ffprobe counts them in tests)
#   Slurm:        slurm-wlm   (tests/drivers/slurm_chain.sh starts a private slurmctld + slurmd for jobs/)
# gcc, libc6-dev and make are on most machines already but not on a minimal Debian image, and nothing
# above pulls them in with --no-install-recommends. python3-ezdxf (0.18, Debian's) reads DXF pattern files.
set -euo pipefail

packages=(
  gcc libc6-dev make cmake pkg-config clang-format
  petsc-dev libopenmpi-dev openmpi-bin libhdf5-openmpi-dev libmetis-dev libyaml-dev libopenblas0-serial
  hdf5-tools python3-h5py python3-matplotlib python3-numpy python3-ezdxf
  paraview python3-paraview xvfb xauth ffmpeg
  slurm-wlm
)

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Abbrev}' "$package" 2>/dev/null || true)
  [[ $status == ii* ]] || missing+=("$package")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install_deps: all ${#packages[@]} packages are installed"
  exit 0
fi

sudo=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install_deps: not root and no sudo; install as root: ${missing[*]}" >&2; exit 1; }
  sudo=(sudo)
fi
echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -q
"${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
