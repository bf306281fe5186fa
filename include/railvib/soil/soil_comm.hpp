// railvib/soil: the communicator of a soil model spread over processes (MPI ranks).
//
// The soil is the one stage that outgrows a machine; it is split into slabs of
// element columns along x (partition.hpp), one per rank, and the ranks talk
// through this interface only: the solver exchanges the nodal forces of the
// node planes two slabs share, the soil model sums its outputs on rank 0.
// Rank 0 is the only rank that talks to the outside (ROS, files).
//
// Two implementations: a serial one (one rank, no MPI call at all) and
// MPI_COMM_WORLD (OpenMPI). worldSoilComm() picks MPI only when the process was
// started by an MPI launcher (mpirun / mpiexec set OMPI_COMM_WORLD_SIZE, or
// PMI_SIZE / PMIX_RANK for other launchers): a plain start never initialises
// MPI, so the tool and the nodes work unchanged without mpirun.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace railvib::soil {

class SoilComm {
 public:
  virtual ~SoilComm() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  bool root() const { return rank() == 0; }
  /// Ranks of this communicator on this host (they share its cores).
  virtual int ranksOnThisHost() const = 0;
  /// "serial" or "mpi".
  virtual std::string kind() const = 0;

  /// Start exchanging with the neighbours rank - 1 (low) and rank + 1 (high), non-blocking: send
  /// send_low / send_high, receive into recv_low / recv_high (bytes each; 0 = no neighbour on that
  /// side). The buffers must stay untouched until finishExchange().
  virtual void startExchange(const void* send_low, void* recv_low, size_t bytes_low, const void* send_high,
                             void* recv_high, size_t bytes_high) = 0;
  virtual void finishExchange() = 0;
  /// Let an exchange in flight advance (MPI moves a message above the eager size only inside an MPI
  /// call, so the solver calls this between pieces of the interior work); never blocks.
  virtual void progressExchange() = 0;

  /// Broadcast bytes from rank 0 (every rank passes a buffer of the same size).
  virtual void broadcast(void* data, size_t bytes) = 0;
  void broadcastString(std::string& text);
  void broadcastDoubles(std::vector<double>& values);
  /// Element-wise sum over the ranks, result on rank 0 only (the others' buffers are unspecified after).
  virtual void sumToRoot(double* values, size_t n) = 0;
  virtual void sumToRoot(float* values, size_t n) = 0;
  /// Every rank's `n` values, in rank order, on every rank (all.size() = n * size()).
  virtual void allGather(const double* mine, size_t n, std::vector<double>& all) = 0;
  /// Element-wise sum over the ranks, added in rank order: the same bits on every rank (`scratch`: the
  /// gathered values, kept by the caller to avoid an allocation per call).
  void sumInRankOrder(double* values, size_t n, std::vector<double>& scratch);
  /// Smallest / largest value over the ranks, on every rank.
  virtual double minimum(double value) = 0;
  virtual double maximum(double value) = 0;
  virtual void barrier() = 0;
  /// A barrier that sleeps while it waits (MPI's own barrier spins on a core): for a rank that must keep
  /// out of the way of another's timing.
  virtual void waitQuietly() = 0;
  /// Stop every rank (an error no rank can recover from); never returns.
  [[noreturn]] virtual void abort(const std::string& why, int code = 1) = 0;

  /// Bytes this rank sent in halo exchanges since construction (the scaling figures).
  uint64_t haloBytesSent() const { return halo_bytes_sent_; }
  uint64_t haloExchanges() const { return halo_exchanges_; }
  /// Wall seconds spent in finishExchange() waiting for the neighbours' planes (communication the
  /// interior work did not hide, plus the neighbours' load imbalance).
  double haloWaitSeconds() const { return halo_wait_s_; }

 protected:
  uint64_t halo_bytes_sent_ = 0, halo_exchanges_ = 0;
  double halo_wait_s_ = 0.0;
};

/// One rank, no MPI.
std::shared_ptr<SoilComm> serialSoilComm();
/// Whether this process was started by an MPI launcher (see above).
bool startedByMpiLauncher();
/// MPI_COMM_WORLD if started by an MPI launcher (MPI initialised once, finalised at exit), else
/// serialSoilComm(). Throws std::runtime_error if MPI cannot start.
std::shared_ptr<SoilComm> worldSoilComm();

}  // namespace railvib::soil
