# quiver_find_opencv(MODULES...): the targets opencv_<module> for the modules asked for.
# OpenCV's own CMake package when it is installed (Debian's libopencv-dev, which pulls every
# module); else the modules from Debian's split packages (libopencv-core-dev,
# libopencv-imgproc-dev, libopencv-imgcodecs-dev), which carry headers and libraries but no CMake
# package: what `./run.sh demo` installs for the Barthel agents (scripts/install-deps.sh --demo).
function(quiver_find_opencv)
  find_package(OpenCV QUIET COMPONENTS ${ARGN})
  if(OpenCV_FOUND)
    return()
  endif()
  find_path(QUIVER_OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4
    DOC "OpenCV's headers (libopencv-core-dev)" REQUIRED)
  foreach(module ${ARGN})
    if(TARGET opencv_${module})
      continue()
    endif()
    find_library(QUIVER_OPENCV_${module}_LIBRARY opencv_${module}
      DOC "OpenCV's ${module} module (libopencv-${module}-dev)" REQUIRED)
    add_library(opencv_${module} SHARED IMPORTED GLOBAL)
    set_target_properties(opencv_${module} PROPERTIES
      IMPORTED_LOCATION ${QUIVER_OPENCV_${module}_LIBRARY}
      INTERFACE_INCLUDE_DIRECTORIES ${QUIVER_OPENCV_INCLUDE_DIR})
  endforeach()
  message(STATUS "OpenCV: no CMake package (libopencv-dev); found ${ARGN} in ${QUIVER_OPENCV_INCLUDE_DIR}")
endfunction()
