# Every dependency is a Debian 12 package (see tools/install-deps.sh).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(HDF5 REQUIRED COMPONENTS C)
find_package(VTK 9 REQUIRED COMPONENTS CommonCore CommonDataModel CommonMisc IOXML)
find_package(CLI11 REQUIRED)
find_package(tomlplusplus REQUIRED)
find_package(fmt REQUIRED)
find_package(nlohmann_json 3 REQUIRED)  # OpenSees JSON models in, CB-Geo MPM input out
find_package(OpenMP REQUIRED COMPONENTS CXX)
find_path(NANOFLANN_INCLUDE_DIR nanoflann.hpp REQUIRED)

# HDF5's CMake module gives variables, not a target: wrap them once.
add_library(slide_hdf5 INTERFACE)
target_include_directories(slide_hdf5 SYSTEM INTERFACE ${HDF5_C_INCLUDE_DIRS})
target_link_libraries(slide_hdf5 INTERFACE ${HDF5_C_LIBRARIES})
target_compile_definitions(slide_hdf5 INTERFACE ${HDF5_C_DEFINITIONS})

add_library(slide_nanoflann INTERFACE)
target_include_directories(slide_nanoflann SYSTEM INTERFACE ${NANOFLANN_INCLUDE_DIR})
