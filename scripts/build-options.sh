# CMake options of the two builds run.sh makes (sourced by run.sh and by
# tests/tools/lean_executables_test.sh): bash arrays.
#
# Every component, test and tool: `./run.sh test` and `./run.sh build` (explicit, so that a build
# folder the demo configured gets everything again).
everything=(-DQUIVER_WITH_INTEROP=ON -DQUIVER_WITH_KINEMATICS=ON -DQUIVER_WITH_RENDER=ON -DQUIVER_BUILD_TESTS=ON
  -DQUIVER_BUILD_PYTHON=ON -DQUIVER_INSTALL=ON)
# What `./run.sh demo` needs (quiver-barthel): no world converters, kinematics, renderers,
# viewer, tests or Python. Its objects are the ones the full build makes (same flags), so that a
# later `./run.sh test` reuses them.
demo_only=(-DQUIVER_WITH_INTEROP=OFF -DQUIVER_WITH_KINEMATICS=OFF -DQUIVER_WITH_RENDER=OFF -DQUIVER_BUILD_TESTS=OFF
  -DQUIVER_BUILD_PYTHON=OFF -DQUIVER_INSTALL=OFF)
