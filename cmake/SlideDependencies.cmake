# Every dependency is a Debian 12 package (see tools/install-deps.sh).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
# The MPI build (docs/parallel.md): OpenMPI and Debian's parallel HDF5 (h5pcc), for
# mpirun -np N mpm-solve. Off by default: the serial build needs neither.
option(SLIDE_MPI "Build for MPI: mpm-solve on several ranks, collective parallel-HDF5 checkpoints" OFF)
if(SLIDE_MPI)
  find_package(MPI REQUIRED COMPONENTS C CXX)
  set(HDF5_PREFER_PARALLEL TRUE)
endif()
find_package(HDF5 REQUIRED COMPONENTS C)
if(SLIDE_MPI AND NOT HDF5_IS_PARALLEL)
  message(FATAL_ERROR "SLIDE_MPI=ON needs the parallel HDF5 (Debian: libhdf5-openmpi-dev; "
                      "tools/install-deps.sh --mpi installs it), found the serial one: ${HDF5_C_LIBRARIES}")
endif()
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

# Every target sees SLIDE_MPI (0 or 1): common/base/ranks.hpp and the collective
# checkpoint switch on it.
add_library(slide_mpi INTERFACE)
if(SLIDE_MPI)
  target_compile_definitions(slide_mpi INTERFACE SLIDE_MPI=1)
  target_link_libraries(slide_mpi INTERFACE MPI::MPI_CXX MPI::MPI_C)
else()
  target_compile_definitions(slide_mpi INTERFACE SLIDE_MPI=0)
endif()

add_library(slide_nanoflann INTERFACE)
target_include_directories(slide_nanoflann SYSTEM INTERFACE ${NANOFLANN_INCLUDE_DIR})
