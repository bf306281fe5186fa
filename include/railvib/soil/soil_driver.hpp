// The soil model spread over MPI ranks, driven from rank 0 alone (docs/soil.md, "MPI ranks").
//
// SoilModel's stepping and output calls are collective: every rank must make them in the same order.
// A caller that lives on rank 0 only (the soil node, which alone talks ROS) drives a SoilDriver; every
// other rank sits in SoilDriver::serve(), which receives each call by broadcast and repeats it on its
// own copy of the model. With one rank the driver is a pass-through.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "railvib/soil/soil_comm.hpp"
#include "railvib/soil/soil_model.hpp"

namespace railvib::soil {

class SoilDriver {
 public:
  /// Builds the model on every rank from the same setup text (e.g. the merged scenario YAML) and the
  /// sleeper positions; runs on every rank with that rank's communicator.
  using Factory = std::function<std::unique_ptr<SoilModel>(
      const std::string& setup, const std::vector<double>& sleeper_x_m, std::shared_ptr<SoilComm> comm)>;

  /// Rank 0 only (throws elsewhere).
  SoilDriver(std::shared_ptr<SoilComm> comm, Factory factory);
  /// Tells the other ranks to stop serving (their serve() returns).
  ~SoilDriver();
  SoilDriver(const SoilDriver&) = delete;
  SoilDriver& operator=(const SoilDriver&) = delete;

  /// Build the model everywhere; once.
  void create(const std::string& setup, const std::vector<double>& sleeper_x_m);
  bool created() const { return model_ != nullptr; }
  /// Rank 0's model, for queries that are not collective (summary, receivers, time).
  const SoilModel& model() const;

  void pushLoads(uint64_t first_index, const double* forces_n, size_t frames);
  void finishLoads();
  uint64_t advance(double t_target_s);
  /// As SoilModel::finishRun; after_slice runs on rank 0 only, and its false stops every rank.
  uint64_t finishRun(double t_end_s, double slice_s, const std::function<bool()>& after_slice = {});
  /// The outputs since the last call, complete on rank 0 (the vectors are replaced).
  void takeOutputs(ReceiverBlock& receivers, std::vector<SurfaceSnapshot>& snapshots,
                   std::vector<SectionSnapshot>& sections);

  /// Ranks other than 0: repeat rank 0's calls until its driver is destroyed. Returns 0, or rethrows
  /// what the model threw (the caller then aborts the run: rank 0 cannot go on without this rank).
  static int serve(std::shared_ptr<SoilComm> comm, const Factory& factory);

 private:
  struct Command;
  void send(const Command& c, const void* payload, size_t bytes);

  std::shared_ptr<SoilComm> comm_;
  Factory factory_;
  std::unique_ptr<SoilModel> model_;
};

}  // namespace railvib::soil
