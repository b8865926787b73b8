# Dependency lookup: Debian 12 packages only (tools/install-deps.sh installs them).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(Boost 1.74 REQUIRED)            # Boost.DLL is header-only
find_package(spdlog REQUIRED)                # the compiled library: one logger registry for all
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
find_package(HDF5 REQUIRED COMPONENTS C)     # FindHDF5 (hdf5-helpers), no config file
find_package(Threads REQUIRED)
find_package(NLopt REQUIRED)                 # L-BFGS for the least-action orbit finder
find_package(OpenMP REQUIRED COMPONENTS CXX)  # the exact mutual potential sums its surface in parallel (libgomp, part of g++)
if(NOETHER_BUILD_PYTHON)
  # Debian's python3 (where python3-numpy and python3-h5py are), not a python3 earlier on the PATH.
  if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python_EXECUTABLE /usr/bin/python3)
  endif()
  find_package(Python 3.9 REQUIRED COMPONENTS Interpreter Development.Module)
  set(PYBIND11_FINDPYTHON ON)
  find_package(pybind11 2.10 CONFIG REQUIRED)  # pybind11-dev
endif()
