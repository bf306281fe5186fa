// railvib ROS layer: hold stream blocks until their latched layout is known.
//
// A stream (SoilLoads, SurfaceVelocities, BuildingResponse) and the latched
// topic describing its points (SleeperLayout, PointLayout) arrive on two
// connections with no order between them: the first blocks may come before
// the layout. The gate keeps them, in arrival order, and runs them once the
// layout has been handled, so no block is lost or reordered.
#pragma once

#include <functional>
#include <utility>
#include <vector>

namespace railvib::ros_io {

class LayoutGate {
 public:
  bool isOpen() const { return open_; }

  /// Run `process` now if the layout is known, else keep it for open().
  void run(std::function<void()> process) {
    if (open_) {
      process();
    } else {
      held_.push_back(std::move(process));
    }
  }

  /// The layout is known: run the held blocks in arrival order (idempotent).
  void open() {
    if (open_) return;
    open_ = true;
    auto held = std::move(held_);
    held_.clear();
    for (auto& process : held) process();
  }

  size_t heldCount() const { return held_.size(); }

 private:
  bool open_ = false;
  std::vector<std::function<void()>> held_;
};

}  // namespace railvib::ros_io
