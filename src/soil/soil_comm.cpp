// railvib/soil: serial and MPI communicators (soil_comm.hpp).
#include "railvib/soil/soil_comm.hpp"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace railvib::soil {

void SoilComm::broadcastString(std::string& text) {
  uint64_t n = text.size();
  broadcast(&n, sizeof(n));
  text.resize(n);
  if (n > 0) broadcast(text.data(), n);
}

void SoilComm::broadcastDoubles(std::vector<double>& values) {
  uint64_t n = values.size();
  broadcast(&n, sizeof(n));
  values.resize(n);
  if (n > 0) broadcast(values.data(), n * sizeof(double));
}

void SoilComm::sumInRankOrder(double* values, size_t n, std::vector<double>& scratch) {
  allGather(values, n, scratch);
  std::fill(values, values + n, 0.0);
  for (size_t r = 0; r < scratch.size() / n; ++r) {
    for (size_t q = 0; q < n; ++q) values[q] += scratch[r * n + q];
  }
}

namespace {

class SerialComm final : public SoilComm {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  std::string kind() const override { return "serial"; }
  void startExchange(const void*, void*, size_t bytes_low, const void*, void*, size_t bytes_high) override {
    if (bytes_low != 0 || bytes_high != 0) throw std::logic_error("serial soil communicator: no neighbours");
  }
  void finishExchange() override {}
  int ranksOnThisHost() const override { return 1; }
  void progressExchange() override {}
  void broadcast(void*, size_t) override {}
  void sumToRoot(double*, size_t) override {}
  void sumToRoot(float*, size_t) override {}
  void allGather(const double* mine, size_t n, std::vector<double>& all) override { all.assign(mine, mine + n); }
  double minimum(double v) override { return v; }
  double maximum(double v) override { return v; }
  void barrier() override {}
  void waitQuietly() override {}
  [[noreturn]] void abort(const std::string& why, int code) override {
    std::cerr << "soil: " << why << "\n";
    std::exit(code);
  }
};

int checkedCount(size_t bytes) {
  if (bytes > static_cast<size_t>(INT_MAX)) throw std::length_error("soil MPI: message above 2 GB");
  return static_cast<int>(bytes);
}

void check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) {
    char text[MPI_MAX_ERROR_STRING];
    int len = 0;
    MPI_Error_string(rc, text, &len);
    throw std::runtime_error(std::string("soil MPI: ") + what + ": " + std::string(text, static_cast<size_t>(len)));
  }
}

void finalizeAtExit() {
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  if (initialised && !finalised) MPI_Finalize();
}

class MpiComm final : public SoilComm {
 public:
  MpiComm() {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) {
      int provided = 0;
      // Only the thread that built the model calls MPI (OpenMP threads never do): FUNNELED.
      check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
      std::atexit(finalizeAtExit);
    }
    // Errors come back as codes (turned into exceptions) instead of aborting inside MPI.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    MPI_Comm host;
    check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &host),
          "MPI_Comm_split_type");
    MPI_Comm_size(host, &host_size_);
    MPI_Comm_free(&host);
  }
  int ranksOnThisHost() const override { return host_size_; }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::string kind() const override { return "mpi"; }

  void startExchange(const void* send_low, void* recv_low, size_t bytes_low, const void* send_high, void* recv_high,
                     size_t bytes_high) override {
    if (pending_ != 0) throw std::logic_error("soil MPI: an exchange is already in flight");
    // Tag = direction of travel: 1 towards the higher rank, 2 towards the lower.
    if (bytes_low > 0) {
      check(MPI_Irecv(recv_low, checkedCount(bytes_low), MPI_BYTE, rank_ - 1, 1, MPI_COMM_WORLD, &req_[pending_++]),
            "MPI_Irecv");
      check(MPI_Isend(send_low, checkedCount(bytes_low), MPI_BYTE, rank_ - 1, 2, MPI_COMM_WORLD, &req_[pending_++]),
            "MPI_Isend");
    }
    if (bytes_high > 0) {
      check(MPI_Irecv(recv_high, checkedCount(bytes_high), MPI_BYTE, rank_ + 1, 2, MPI_COMM_WORLD, &req_[pending_++]),
            "MPI_Irecv");
      check(MPI_Isend(send_high, checkedCount(bytes_high), MPI_BYTE, rank_ + 1, 1, MPI_COMM_WORLD, &req_[pending_++]),
            "MPI_Isend");
    }
    halo_bytes_sent_ += bytes_low + bytes_high;
    ++halo_exchanges_;
  }
  void finishExchange() override {
    if (pending_ == 0) return;
    const double t0 = MPI_Wtime();
    check(MPI_Waitall(pending_, req_, MPI_STATUSES_IGNORE), "MPI_Waitall (halo exchange)");
    halo_wait_s_ += MPI_Wtime() - t0;
    pending_ = 0;
  }
  void progressExchange() override {
    if (pending_ == 0) return;
    int done = 0;
    check(MPI_Testall(pending_, req_, &done, MPI_STATUSES_IGNORE), "MPI_Testall (halo exchange)");
  }
  void broadcast(void* data, size_t bytes) override {
    check(MPI_Bcast(data, checkedCount(bytes), MPI_BYTE, 0, MPI_COMM_WORLD), "MPI_Bcast");
  }
  void sumToRoot(double* values, size_t n) override {
    check(
        MPI_Reduce(rank_ == 0 ? MPI_IN_PLACE : values, values, checkedCount(n), MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD),
        "MPI_Reduce");
  }
  void sumToRoot(float* values, size_t n) override {
    check(
        MPI_Reduce(rank_ == 0 ? MPI_IN_PLACE : values, values, checkedCount(n), MPI_FLOAT, MPI_SUM, 0, MPI_COMM_WORLD),
        "MPI_Reduce");
  }
  void allGather(const double* mine, size_t n, std::vector<double>& all) override {
    all.resize(n * static_cast<size_t>(size_));
    check(MPI_Allgather(mine, checkedCount(n), MPI_DOUBLE, all.data(), checkedCount(n), MPI_DOUBLE, MPI_COMM_WORLD),
          "MPI_Allgather");
  }
  double minimum(double v) override {
    double out = v;
    check(MPI_Allreduce(&v, &out, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD), "MPI_Allreduce");
    return out;
  }
  double maximum(double v) override {
    double out = v;
    check(MPI_Allreduce(&v, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
    return out;
  }
  void barrier() override { check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier"); }
  void waitQuietly() override {
    MPI_Request req;
    check(MPI_Ibarrier(MPI_COMM_WORLD, &req), "MPI_Ibarrier");
    for (int done = 0;;) {
      check(MPI_Test(&req, &done, MPI_STATUS_IGNORE), "MPI_Test (barrier)");
      if (done) return;
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
  }
  [[noreturn]] void abort(const std::string& why, int code) override {
    std::cerr << "soil rank " << rank_ << " of " << size_ << ": " << why << "; stopping every rank" << std::endl;
    MPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code);
  }

 private:
  int rank_ = 0, size_ = 1, host_size_ = 1;
  MPI_Request req_[4];
  int pending_ = 0;
};

}  // namespace

std::shared_ptr<SoilComm> serialSoilComm() { return std::make_shared<SerialComm>(); }

bool startedByMpiLauncher() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(v) != nullptr) return true;
  }
  return false;
}

std::shared_ptr<SoilComm> worldSoilComm() {
  if (!startedByMpiLauncher()) return serialSoilComm();
  static std::once_flag once;
  static std::shared_ptr<SoilComm> world;
  std::call_once(once, [] { world = std::make_shared<MpiComm>(); });
  return world;
}

}  // namespace railvib::soil
