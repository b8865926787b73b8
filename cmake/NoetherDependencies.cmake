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
