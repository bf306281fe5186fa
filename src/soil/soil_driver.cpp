#include "railvib/soil/soil_driver.hpp"

#include <stdexcept>

namespace railvib::soil {

// One broadcast per call: what to do and its scalar arguments; the bulk (setup text, positions,
// loads) follows as a second broadcast.
struct SoilDriver::Command {
  enum Code : uint32_t { kCreate = 1, kPushLoads, kFinishLoads, kAdvance, kFinishOutputs, kTakeOutputs, kStop };
  uint32_t code = 0;
  uint32_t reserved = 0;
  uint64_t index = 0;  // pushLoads: first sample index
  uint64_t count = 0;  // pushLoads: frames
  double time_s = 0.0;
};

SoilDriver::SoilDriver(std::shared_ptr<SoilComm> comm, Factory factory)
    : comm_(comm ? std::move(comm) : serialSoilComm()), factory_(std::move(factory)) {
  if (!comm_->root()) throw std::logic_error("SoilDriver: only rank 0 drives; the other ranks call serve()");
  if (!factory_) throw std::invalid_argument("SoilDriver: no model factory");
}

SoilDriver::~SoilDriver() {
  if (comm_->size() == 1) return;
  Command c;
  c.code = Command::kStop;
  comm_->broadcast(&c, sizeof c);
}

void SoilDriver::send(const Command& c, const void* payload, size_t bytes) {
  if (comm_->size() == 1) return;
  Command copy = c;
  comm_->broadcast(&copy, sizeof copy);
  if (bytes > 0) comm_->broadcast(const_cast<void*>(payload), bytes);
}

const SoilModel& SoilDriver::model() const {
  if (!model_) throw std::logic_error("SoilDriver: the model is not created yet");
  return *model_;
}

void SoilDriver::create(const std::string& setup, const std::vector<double>& sleeper_x_m) {
  if (model_) throw std::logic_error("SoilDriver: the model exists already");
  if (comm_->size() > 1) {
    Command c;
    c.code = Command::kCreate;
    send(c, nullptr, 0);
    std::string text = setup;
    std::vector<double> x = sleeper_x_m;
    comm_->broadcastString(text);
    comm_->broadcastDoubles(x);
  }
  // Collective (the solver sums masses and agrees on the step): every rank builds it now.
  model_ = factory_(setup, sleeper_x_m, comm_);
}

void SoilDriver::pushLoads(uint64_t first_index, const double* forces_n, size_t frames) {
  // Not collective: rank 0 checks the block on its own model first, the others only get what passed.
  if (!model_) throw std::logic_error("SoilDriver: loads before the model");
  model_->pushLoads(first_index, forces_n, frames);
  Command c;
  c.code = Command::kPushLoads;
  c.index = first_index;
  c.count = frames;
  send(c, forces_n, frames * model_->loadsPerFrame() * sizeof(double));
}

void SoilDriver::finishLoads() {
  model();
  model_->finishLoads();
  Command c;
  c.code = Command::kFinishLoads;
  send(c, nullptr, 0);
}

uint64_t SoilDriver::advance(double t_target_s) {
  model();
  Command c;
  c.code = Command::kAdvance;
  c.time_s = t_target_s;
  send(c, nullptr, 0);
  return model_->advance(t_target_s);
}

uint64_t SoilDriver::finishRun(double t_end_s, double slice_s, const std::function<bool()>& after_slice) {
  // SoilModel::finishRun's loop, call by call, so that the other ranks follow each slice.
  if (!(slice_s > 0.0)) throw std::invalid_argument("SoilDriver::finishRun: slice_s must be > 0");
  const SoilModel& m = model();
  uint64_t steps = 0;
  while (m.time() < t_end_s) {
    const uint64_t n = advance(std::min(t_end_s, m.time() + slice_s));
    if (n == 0) break;
    steps += n;
    if (after_slice && !after_slice()) return steps;
  }
  steps += advance(t_end_s + m.dt());
  Command c;
  c.code = Command::kFinishOutputs;
  send(c, nullptr, 0);
  model_->finishOutputs();
  return steps;
}

void SoilDriver::takeOutputs(ReceiverBlock& receivers, std::vector<SurfaceSnapshot>& snapshots,
                             std::vector<SectionSnapshot>& sections) {
  model();
  Command c;
  c.code = Command::kTakeOutputs;
  send(c, nullptr, 0);
  snapshots.clear();
  sections.clear();
  model_->takeReceiverSamples(receivers);
  model_->takeSnapshots(snapshots);
  model_->takeSectionSnapshots(sections);
}

int SoilDriver::serve(std::shared_ptr<SoilComm> comm, const Factory& factory) {
  if (!comm || comm->root()) throw std::logic_error("SoilDriver::serve: for the ranks other than 0");
  std::unique_ptr<SoilModel> model;
  ReceiverBlock receivers;
  std::vector<SurfaceSnapshot> snapshots;
  std::vector<SectionSnapshot> sections;
  std::vector<double> loads;
  auto need = [&] {
    if (!model) throw std::logic_error("soil rank " + std::to_string(comm->rank()) + ": a call before the model");
    return model.get();
  };
  for (;;) {
    Command c;
    comm->broadcast(&c, sizeof c);
    switch (c.code) {
      case Command::kCreate: {
        std::string setup;
        std::vector<double> x;
        comm->broadcastString(setup);
        comm->broadcastDoubles(x);
        model = factory(setup, x, comm);
        break;
      }
      case Command::kPushLoads:
        loads.resize(c.count * need()->loadsPerFrame());
        if (!loads.empty()) comm->broadcast(loads.data(), loads.size() * sizeof(double));
        model->pushLoads(c.index, loads.data(), c.count);
        break;
      case Command::kFinishLoads:
        need()->finishLoads();
        break;
      case Command::kAdvance:
        need()->advance(c.time_s);
        break;
      case Command::kFinishOutputs:
        need()->finishOutputs();
        break;
      case Command::kTakeOutputs:
        snapshots.clear();
        sections.clear();
        need()->takeReceiverSamples(receivers);
        model->takeSnapshots(snapshots);
        model->takeSectionSnapshots(sections);
        break;
      case Command::kStop:
        return 0;
      default:
        throw std::runtime_error("soil rank " + std::to_string(comm->rank()) + ": unknown command " +
                                 std::to_string(c.code) + " from rank 0");
    }
  }
}

}  // namespace railvib::soil
