# Shared by the scripts: paths, the Debian packages the project needs, and the workspace build.
# Sourced, not run.

PACKAGE_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WORKSPACE="${RIGID_BODY_SIM_WS:-$PACKAGE_DIR/ws}"

# Debian's ROS 1 lives in /usr; the pyenv python3 on some PATHs lacks catkin_pkg, so /usr/bin comes first.
export PATH="/usr/bin:/bin:$PATH"

# Everything the package builds, tests and runs with, by Debian package name (rosdep has no index here).
DEBIAN_PACKAGES=(
  build-essential cmake
  ros-core-dev rosbash catkin python3-catkin-pkg python3-rospkg
  libtf2-ros-dev libtf2-msgs-dev libtf2-eigen-dev libtf2-geometry-msgs-dev
  ros-nav-msgs ros-geometry-msgs ros-std-srvs libstd-srvs-dev libnav-msgs-dev libgeometry-msgs-dev
  python3-rostest librostest-dev python3-rostopic python3-roslaunch
  python3-rospy python3-rosunit python3-nav-msgs python3-geometry-msgs python3-std-msgs python3-std-srvs python3-tf2-msgs python3-tf2-ros
  libeigen3-dev libgtest-dev libboost-math-dev libbenchmark-dev libbullet-dev pkg-config
  libvisualization-msgs-dev ros-visualization-msgs python3-visualization-msgs
  libsensor-msgs-dev ros-sensor-msgs python3-sensor-msgs
  libnodeletlib-dev libnodeletlib-tools pluginlib-dev libyaml-cpp-dev python3-yaml
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure liburdf-dev liburdfdom-dev
  gnuplot-nox libdiagnostic-updater-dev python3-diagnostic-msgs libdiagnostic-msgs-dev libroslib-dev libros-rosgraph-msgs-dev python3-rosgraph-msgs
)

# Installs the packages that are missing (apt-get update once, only when something is missing).
install_dependencies() {
  local missing=()
  for package in "${DEBIAN_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    return 0
  fi
  echo "Installing Debian packages: ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
}

# Makes the workspace and builds it with catkin_make. src/rigid_body_sim is a real folder whose entries
# link to this checkout's top-level entries (all but the workspace itself): a link to the checkout as a
# whole would put the workspace inside the package, and rosrun's `find -L` would loop through it.
link_package() {
  local package="$WORKSPACE/src/rigid_body_sim"
  [ -L "$package" ] && rm "$package"
  mkdir -p "$package"
  find "$package" -maxdepth 1 -type l ! -exec test -e {} \; -delete  # entries the checkout no longer has
  local entry
  for entry in "$PACKAGE_DIR"/*; do
    [ "$(cd "$entry" 2>/dev/null && pwd -P)" = "$(cd "$WORKSPACE" && pwd -P)" ] && continue
    ln -sfn "$entry" "$package/$(basename "$entry")"
  done
  # The example downstream packages build and test beside it, as a user's own would (catkin does not look
  # for packages inside a package's folder).
  find "$WORKSPACE/src" -maxdepth 1 -type l ! -exec test -e {} \; -delete
  for entry in "$PACKAGE_DIR"/examples/*/; do
    [ -f "$entry/package.xml" ] && ln -sfn "${entry%/}" "$WORKSPACE/src/$(basename "$entry")"
  done
  return 0
}

build_workspace() {
  mkdir -p "$WORKSPACE/src"
  link_package
  (cd "$WORKSPACE" && catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release "$@")
}

source_workspace() {
  # shellcheck disable=SC1091
  set +u
  source "$WORKSPACE/devel/setup.bash"
  set -u 2>/dev/null || true
}

# A ROS master of our own on port $1, beside any other. It, and every PID later added to STOP_PIDS, is
# stopped when the script exits.
start_private_master() {
  export ROS_MASTER_URI="http://localhost:$1"
  roscore -p "$1" >/dev/null 2>&1 &
  STOP_PIDS="$!"
  trap 'kill $STOP_PIDS 2>/dev/null; wait 2>/dev/null' EXIT
  sleep 3
}

# The set-up of the scripts that run the node against a master of their own on port $1: what the package
# needs installed, the workspace built and sourced, the master started.
prepare_node_run() {
  install_dependencies
  build_workspace
  source_workspace
  start_private_master "$1"
}

# The machine a benchmark ran on, for the first line of its output: "N cores, CPU model".
machine_description() {
  echo "$(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p')"
}

# The load scripts' scene: a swarm of $1 bodies (scripts/make_scene.py; half take wrenches; tf and odom at
# 100 Hz, dt 1 ms, integrator $INTEGRATOR or rk4) written to the file $2. Sets SWARM_FIRST to the name of
# its first body (the names are zero-padded to the width of the last index).
write_swarm_scene() {
  /usr/bin/python3 "$PACKAGE_DIR/scripts/make_scene.py" --bodies "$1" --with-input $((($1 + 1) / 2)) \
    --integrator "${INTEGRATOR:-rk4}" --publish tf,odom >"$2"
  local last=$(($1 - 1)) width
  width=${#last}
  ((width < 2)) && width=2
  SWARM_FIRST=$(printf "swarm_%0${width}d" 0)
}
