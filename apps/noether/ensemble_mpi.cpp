// noether ensemble under mpirun (docs/ensembles.md, "Across machines"): rank 0 holds the file and
// hands out samples one at a time (dynamic distribution); every other rank runs the samples it is
// given and sends back their results. Only the ensemble command uses MPI.
#include "ensemble_mpi.hpp"

#include <noether/error.hpp>

#include <mpi.h>

#include <cstdlib>
#include <iostream>

namespace noether::app {

namespace {

enum Tag : int { kReady = 1, kAssign = 2, kResult = 3, kMessage = 4 };

// The other ranks, as run_ensemble sees them.
class MpiWorkers final : public RemoteWorkers {
 public:
  explicit MpiWorkers(int size) : size_(size) {}
  std::size_t count() const override { return static_cast<std::size_t>(size_ - 1); }
  void poll(std::vector<std::pair<std::size_t, SampleResult>>& results, std::vector<int>& idle) override {
    for (;;) {
      int flag = 0;
      MPI_Status status;
      MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
      if (!flag) return;
      const int source = status.MPI_SOURCE;
      if (status.MPI_TAG == kReady) {
        MPI_Recv(nullptr, 0, MPI_BYTE, source, kReady, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        idle.push_back(source);
      } else if (status.MPI_TAG == kResult) {
        int n = 0;
        MPI_Get_count(&status, MPI_DOUBLE, &n);
        std::vector<double> numbers(static_cast<std::size_t>(n));
        MPI_Recv(numbers.data(), n, MPI_DOUBLE, source, kResult, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        MPI_Status text_status;
        MPI_Probe(source, kMessage, MPI_COMM_WORLD, &text_status);
        int chars = 0;
        MPI_Get_count(&text_status, MPI_CHAR, &chars);
        std::string message(static_cast<std::size_t>(chars), '\0');
        MPI_Recv(message.data(), chars, MPI_CHAR, source, kMessage, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        const auto index = static_cast<std::size_t>(numbers.front());
        numbers.erase(numbers.begin());
        results.emplace_back(index, SampleResult::unpack(numbers, std::move(message)));
        idle.push_back(source);  // a worker that sent a result waits for its next sample
      } else {
        throw Error("ensemble: an unexpected MPI message (tag " + std::to_string(status.MPI_TAG) + ")");
      }
    }
  }
  void assign(int worker, std::size_t index) override {
    const auto value = static_cast<unsigned long long>(index);
    MPI_Send(&value, 1, MPI_UNSIGNED_LONG_LONG, worker, kAssign, MPI_COMM_WORLD);
  }

 private:
  int size_;
};

void serve(const EnsemblePlan& plan, const std::filesystem::path& output) {
  PluginRegistry registry;
  MPI_Send(nullptr, 0, MPI_BYTE, 0, kReady, MPI_COMM_WORLD);
  for (;;) {
    unsigned long long index = 0;
    MPI_Recv(&index, 1, MPI_UNSIGNED_LONG_LONG, 0, kAssign, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (index == static_cast<unsigned long long>(RemoteWorkers::kNone)) return;
    const SampleResult r = plan.run(static_cast<std::size_t>(index), registry, output);
    std::vector<double> numbers = r.pack();
    numbers.insert(numbers.begin(), static_cast<double>(index));
    MPI_Send(numbers.data(), static_cast<int>(numbers.size()), MPI_DOUBLE, 0, kResult, MPI_COMM_WORLD);
    MPI_Send(r.message.data(), static_cast<int>(r.message.size()), MPI_CHAR, 0, kMessage, MPI_COMM_WORLD);
  }
}

}  // namespace

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (const char* s = std::getenv(v); s && std::atoi(s) > 0 && std::string(v) != "PMIX_RANK") return std::atoi(s) > 1;
  return false;
}

int mpi_ensemble(const std::function<int(RemoteWorkers*)>& lead, const std::filesystem::path& scene_file,
                 const std::vector<std::string>& overrides, const EnsembleOptions& options,
                 const std::filesystem::path& output) {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int code = 0;
  try {
    if (rank == 0) {
      // The plan first: its errors are every rank's (the same command line), so nobody waits.
      bool planned = false;
      try {
        EnsemblePlan check(scene_file, overrides, options);
        planned = true;
        MpiWorkers workers(size);
        code = lead(&workers);
      } catch (const Error& e) {
        std::cerr << "noether: " << e.what() << "\n";
        code = 2;
        if (planned)  // the workers are serving: stop them
          for (int r = 1; r < size; ++r) {
            const auto none = static_cast<unsigned long long>(RemoteWorkers::kNone);
            MPI_Send(&none, 1, MPI_UNSIGNED_LONG_LONG, r, kAssign, MPI_COMM_WORLD);
          }
      }
    } else {
      // The same plan from the same command line (its errors are rank 0's to print).
      std::unique_ptr<EnsemblePlan> plan;
      try {
        plan = std::make_unique<EnsemblePlan>(scene_file, overrides, options);
      } catch (const Error&) {
        code = 2;
      }
      if (plan) serve(*plan, output);
    }
  } catch (const Error& e) {
    std::cerr << "noether: rank " << rank << ": " << e.what() << "\n";
    MPI_Abort(MPI_COMM_WORLD, 2);
  }
  MPI_Finalize();
  return code;
}

}  // namespace noether::app
