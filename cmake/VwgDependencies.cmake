# The libraries of DESIGN.md. Used by the build (every one) and by the installed vwgConfig.cmake
# (only those of the components asked for): VWG_DEPENDENCIES, when set, lists the ones to find
# among Threads Eigen3 box2d apriltag ompl OpenCV.
# Debian 12 ships OpenCVConfig.cmake only in the large libopencv-dev metapackage; with the split
# packages (libopencv-core-dev, ...) the libraries and headers are found directly and given
# imported targets of the same names.
if(NOT DEFINED VWG_DEPENDENCIES)
  set(VWG_DEPENDENCIES Threads Eigen3 box2d apriltag ompl OpenCV)
endif()
if(Threads IN_LIST VWG_DEPENDENCIES)
  find_package(Threads REQUIRED)  # the frame's worker pool (parallel.hpp)
endif()
if(Eigen3 IN_LIST VWG_DEPENDENCIES)
  find_package(Eigen3 REQUIRED NO_MODULE)
endif()
if(box2d IN_LIST VWG_DEPENDENCIES)
  find_package(box2d REQUIRED)
endif()
if(apriltag IN_LIST VWG_DEPENDENCIES)
  find_package(apriltag REQUIRED)
endif()
if(ompl IN_LIST VWG_DEPENDENCIES)
  find_package(ompl REQUIRED)
endif()

if(OpenCV IN_LIST VWG_DEPENDENCIES)
  set(VWG_OPENCV_COMPONENTS core imgproc imgcodecs videoio calib3d)
  find_package(OpenCV QUIET COMPONENTS ${VWG_OPENCV_COMPONENTS})
  if(NOT OpenCV_FOUND)
    find_path(VWG_OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4 REQUIRED)
    set(OpenCV_LIBS "")
    foreach(component IN LISTS VWG_OPENCV_COMPONENTS)
      find_library(VWG_OPENCV_${component}_LIBRARY opencv_${component} REQUIRED)
      if(NOT TARGET opencv_${component})
        add_library(opencv_${component} UNKNOWN IMPORTED)
        set_target_properties(opencv_${component} PROPERTIES
          IMPORTED_LOCATION "${VWG_OPENCV_${component}_LIBRARY}"
          INTERFACE_INCLUDE_DIRECTORIES "${VWG_OPENCV_INCLUDE_DIR}")
      endif()
      list(APPEND OpenCV_LIBS opencv_${component})
    endforeach()
    message(STATUS "OpenCV: ${VWG_OPENCV_INCLUDE_DIR} (${OpenCV_LIBS}, found without OpenCVConfig.cmake)")
  endif()
endif()
