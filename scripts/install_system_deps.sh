#!/usr/bin/env bash
# Install the system libraries that off-screen rendering (pyvista/VTK) needs on Debian or
# Ubuntu: the EGL loader and Mesa's EGL and DRI (software llvmpipe) drivers.  VTK's wheels
# load libEGL.so.1 at run time, so no X server (and no Xvfb) is needed; skfem_cable.plot sets
# VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow when there is no DISPLAY.
#
# Idempotent: installs nothing when the packages are present.  Exits 0 with a message when
# it cannot install (not root, no apt-get), so callers may run it unconditionally; the
# render test then skips with the reason.
set -euo pipefail

PACKAGES=(libegl1 libegl-mesa0 libgl1-mesa-dri)

missing=()
for pkg in "${PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$pkg")
    fi
done

if [ ${#missing[@]} -eq 0 ]; then
    echo "install_system_deps: rendering libraries present (${PACKAGES[*]})"
    exit 0
fi
if ! command -v apt-get >/dev/null 2>&1; then
    echo "install_system_deps: no apt-get; install an EGL/OpenGL driver yourself" \
         "(wanted: ${missing[*]}); rendering tests will be skipped"
    exit 0
fi
if [ "$(id -u)" -ne 0 ]; then
    echo "install_system_deps: not root; run 'sudo $0' to install ${missing[*]};" \
         "rendering tests will be skipped"
    exit 0
fi
echo "install_system_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install_system_deps: done"
