#!/usr/bin/env bash
# Installs what bezier-subdiv needs to build and test on Debian/Ubuntu:
# the Vulkan loader, Mesa's lavapipe (with VK_EXT_mesh_shader), the Khronos
# validation layer, a C/C++ toolchain, the shaderc/glslang/SPIRV-Tools
# libraries used by the shader tool under tools/, and for the `view` window
# the X11 client libraries winit opens at run time plus Xvfb, the virtual
# X server its test runs under, and a font for bench's plots. Idempotent: rerunning it
# installs nothing that is already there.
#
# On Debian 12 the Mesa in the main suite (22.x) has no mesh shaders on
# lavapipe, so Mesa comes from bookworm-backports. The backports source is
# derived from the machine's own apt sources (same mirror, same keyring),
# never from a host name written here.
set -euo pipefail

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

# fonts-dejavu-core: the TTF `bench` draws its plots' text with.
MAIN_PKGS=(build-essential pkg-config libvulkan1 vulkan-tools
  vulkan-validationlayers libshaderc-dev glslc spirv-tools glslang-tools
  xvfb xauth xdotool libx11-6 libx11-xcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0
  fonts-dejavu-core)

have_all() {
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || return 1
  done
}

# Major version of an installed Debian package, or 0.
pkg_major() {
  local v
  v=$(dpkg-query -W -f='${Version}' "$1" 2>/dev/null || true)
  v=${v#*:}
  echo "${v%%.*}" | grep -E '^[0-9]+$' || echo 0
}

. /etc/os-release
codename="${VERSION_CODENAME:-}"

# Prints the first mirror URI that serves "$codename" in the machine's apt
# sources, from one-line (.list) or deb822 (.sources) files.
main_mirror() {
  local f
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    awk -v s="$codename" '$1=="deb" {
        i=2; if ($2 ~ /^\[/) { while ($i !~ /\]$/) i++; i++ }
        if ($(i+1)==s) { print $i; exit } }' "$f"
  done | head -n 1 | grep . && return 0
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    awk -v s="$codename" 'BEGIN{RS=""; FS="\n"} /(^|\n)Types:[^\n]*deb([ \n]|$)/ {
        uris=""; ok=0
        for (k=1; k<=NF; k++) {
          if ($k ~ /^URIs:/) { uris=$k; sub(/^URIs:[ \t]*/, "", uris) }
          if ($k ~ /^Suites:/) { n=split($k, a, /[ \t]+/); for (j=2; j<=n; j++) if (a[j]==s) ok=1 }
        }
        if (ok && uris!="") { split(uris, u, /[ \t]+/); print u[1]; exit } }' "$f"
  done | head -n 1 | grep .
}

# Prints the Signed-By keyring of the deb822 stanza serving "$codename", if any.
main_keyring() {
  local f
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    awk -v s="$codename" 'BEGIN{RS=""; FS="\n"} {
        key=""; ok=0
        for (k=1; k<=NF; k++) {
          if ($k ~ /^Signed-By:/) { key=$k; sub(/^Signed-By:[ \t]*/, "", key) }
          if ($k ~ /^Suites:/) { n=split($k, a, /[ \t]+/); for (j=2; j<=n; j++) if (a[j]==s) ok=1 }
        }
        if (ok && key!="") { print key; exit } }' "$f"
  done | head -n 1
}

apt_updated=0
apt_update() {
  if [ "$apt_updated" -eq 0 ]; then
    $SUDO apt-get update -qq
    apt_updated=1
  fi
}

export DEBIAN_FRONTEND=noninteractive

if ! have_all "${MAIN_PKGS[@]}"; then
  apt_update
  $SUDO apt-get install -y -qq --no-install-recommends "${MAIN_PKGS[@]}"
fi

# lavapipe with mesh shaders needs Mesa >= 24.1.
if [ "$(pkg_major mesa-vulkan-drivers)" -lt 24 ]; then
  target=()
  if [ "${ID:-}" = debian ] && [ "$codename" = bookworm ]; then
    bp=/etc/apt/sources.list.d/bezier-subdiv-backports.list
    if [ ! -f "$bp" ]; then
      mirror=$(main_mirror) || { echo "install-deps: no apt source for $codename found to derive backports from" >&2; exit 1; }
      key=$(main_keyring)
      opt=""
      [ -n "$key" ] && opt="[signed-by=$key] "
      echo "deb ${opt}${mirror} ${codename}-backports main" | $SUDO tee "$bp" >/dev/null
      apt_updated=0
    fi
    target=(-t "${codename}-backports")
  fi
  apt_update
  $SUDO apt-get install -y -qq --no-install-recommends "${target[@]}" mesa-vulkan-drivers
fi

if [ "$(pkg_major mesa-vulkan-drivers)" -lt 24 ]; then
  echo "install-deps: mesa-vulkan-drivers $(dpkg-query -W -f='${Version}' mesa-vulkan-drivers) has no mesh shaders on lavapipe; need >= 24.1" >&2
  exit 1
fi

echo "install-deps: ok (mesa-vulkan-drivers $(dpkg-query -W -f='${Version}' mesa-vulkan-drivers))"
