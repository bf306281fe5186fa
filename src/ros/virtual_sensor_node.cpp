#include "railvib/ros/virtual_sensor_node.hpp"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/Vector3Stamped.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/Imu.h>

#include <algorithm>
#include <cmath>

#include "railvib/BuildingResponse.h"
#include "railvib/SurfaceVelocities.h"
#include "railvib/VibrationMetrics.h"
#include "railvib/common/names.hpp"
#include "railvib/common/stream_contract.hpp"
#include "railvib/ros/node_config.hpp"
#include "railvib/soil/soil_params.hpp"
#include "railvib/vehicle/vehicle_params.hpp"

namespace railvib::ros_io {

namespace {
constexpr double kGravity_m_s2 = 9.80665;

using Level = signal::VerdictLevel;
static_assert(railvib::VibrationMetrics::VERDICT_OK == static_cast<uint8_t>(Level::Ok) &&
                  railvib::VibrationMetrics::VERDICT_WARN == static_cast<uint8_t>(Level::Warn) &&
                  railvib::VibrationMetrics::VERDICT_ERROR == static_cast<uint8_t>(Level::Error) &&
                  railvib::VibrationMetrics::VERDICT_NOT_APPLICABLE == static_cast<uint8_t>(Level::NotApplicable) &&
                  railvib::VibrationMetrics::VERDICT_NOT_ASSESSABLE == static_cast<uint8_t>(Level::NotAssessable),
              "VibrationMetrics verdicts are signal::VerdictLevel values");
static_assert(railvib::VibrationMetrics::KIND_FREE_FIELD == static_cast<uint8_t>(signal::SensorKind::FreeField) &&
                  railvib::VibrationMetrics::KIND_FOUNDATION == static_cast<uint8_t>(signal::SensorKind::Foundation) &&
                  railvib::VibrationMetrics::KIND_FLOOR == static_cast<uint8_t>(signal::SensorKind::Floor),
              "VibrationMetrics kinds are signal::SensorKind values");
static_assert(diagnostic_msgs::DiagnosticStatus::OK == static_cast<uint8_t>(Level::Ok) &&
                  diagnostic_msgs::DiagnosticStatus::WARN == static_cast<uint8_t>(Level::Warn) &&
                  diagnostic_msgs::DiagnosticStatus::ERROR == static_cast<uint8_t>(Level::Error),
              "diagnostic levels are signal::VerdictLevel values");

template <class Msg>
VirtualSensorNode::InputBlock asInput(const Msg& msg, uint32_t point_count) {
  VirtualSensorNode::InputBlock b;
  b.first_sample_index = msg.first_sample_index;
  b.end_of_stream = msg.end_of_stream;
  b.sample_period_s = msg.sample_period_s;
  b.sample_count = msg.sample_count;
  b.point_count = point_count;
  b.velocity_m_s = &msg.velocity_m_s;
  return b;
}
}  // namespace

VirtualSensorNode::VirtualSensorNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh) {
  const Config config = loadNodeConfig(nh);
  config_ = signal::loadVirtualSensorConfig(config.root());
  limits_ = loadStreamLimits(config.root());
  input_rate_hz_ = soil::loadReceiverRateHz(config.root());
  resolved_hz_ = soil::loadResolvedFrequencyHz(config.root());
  status_ = std::make_unique<NodeStatus>(nh, "virtual_sensor", vehicle::loadPassageParams(config.root()).duration_s);
  bool use_building = true;
  int required_subscribers = 1;
  int block_samples = 100;
  bool publish_clock = false;
  private_nh.param("publish_clock", publish_clock, publish_clock);
  private_nh.param("use_building", use_building, use_building);
  private_nh.param("required_subscribers", required_subscribers, required_subscribers);
  int sensor_topic_subscribers = 0;
  private_nh.param("sensor_topic_subscribers", sensor_topic_subscribers, sensor_topic_subscribers);
  private_nh.param("block_samples", block_samples, block_samples);
  block_samples_ = static_cast<size_t>(std::max(1, block_samples));
  metrics_every_ =
      std::max<uint64_t>(1, static_cast<uint64_t>(std::llround(config_.sample_rate_hz / config_.metrics_rate_hz)));

  for (const auto& setup : config_.sensors) {
    if (setup.source == "building" && !use_building) continue;
    Sensor s;
    s.setup = setup;
    s.imu = BlockPublisher<sensor_msgs::Imu>(nh, names::sensorTopic(setup.spec.name, "imu"), sensor_topic_subscribers);
    s.velocity = BlockPublisher<geometry_msgs::Vector3Stamped>(nh, names::sensorTopic(setup.spec.name, "velocity"),
                                                               sensor_topic_subscribers);
    s.metrics = BlockPublisher<railvib::VibrationMetrics>(nh, names::sensorTopic(setup.spec.name, "metrics"),
                                                          sensor_topic_subscribers);
    sensors_.push_back(std::move(s));
  }
  if (sensors_.empty()) throw std::runtime_error("no virtual sensor configured (virtual_sensors.sensors)");
  samples_publisher_ = BlockPublisher<railvib::SensorSamples>(nh, names::kSensorSamplesTopic, required_subscribers);
  diagnostics_publisher_ = nh.advertise<diagnostic_msgs::DiagnosticArray>(names::kDiagnosticsTopic, 10);
  // Every sensor's metrics on one topic too, so a recorder needs no sensor names.
  all_metrics_publisher_ = nh.advertise<railvib::VibrationMetrics>(names::kSensorMetricsTopic, 0);
  // Live runs: simulation time is how far the sensors have got, the time a monitoring tool sees.
  if (publish_clock) clock_publisher_ = nh.advertise<rosgraph_msgs::Clock>(names::kClockTopic, 100);

  auto has_source = [&](const char* name) {
    return std::any_of(sensors_.begin(), sensors_.end(), [&](const Sensor& s) { return s.setup.source == name; });
  };
  auto add_source = [&](const std::string& name, const char* count_field, const char* layout) -> Source& {
    sources_.push_back(std::make_unique<Source>());
    Source& src = *sources_.back();
    src.name = name;
    src.tracker = std::make_unique<SampleIndexTracker>(name);
    src.count_field = count_field;
    src.layout_name = layout;
    return src;
  };
  if (has_source("soil")) {
    Source& src = add_source("soil", "receiver_count", "the surface_points layout");
    Source* raw = &src;
    src.layout_sub = nh.subscribe<railvib::PointLayout>(
        names::kSurfacePointsTopic, 1,
        boost::function<void(const railvib::PointLayout::ConstPtr&)>(
            [this, raw](const railvib::PointLayout::ConstPtr& m) { onLayout(*raw, *m); }));
    src.data_sub = nh.subscribe<railvib::SurfaceVelocities>(
        names::kSurfaceVelocitiesTopic, 0,
        boost::function<void(const railvib::SurfaceVelocities::ConstPtr&)>(
            [this, raw](const railvib::SurfaceVelocities::ConstPtr& m) {
              raw->gate.run([this, raw, m] { onBlock(*raw, asInput(*m, m->receiver_count)); });
            }));
  }
  if (has_source("building")) {
    Source& src = add_source("building", "point_count", "the building_points layout");
    Source* raw = &src;
    src.layout_sub = nh.subscribe<railvib::PointLayout>(
        names::kBuildingPointsTopic, 1,
        boost::function<void(const railvib::PointLayout::ConstPtr&)>(
            [this, raw](const railvib::PointLayout::ConstPtr& m) { onLayout(*raw, *m); }));
    src.data_sub = nh.subscribe<railvib::BuildingResponse>(
        names::kBuildingResponseTopic, 0,
        boost::function<void(const railvib::BuildingResponse::ConstPtr&)>(
            [this, raw](const railvib::BuildingResponse::ConstPtr& m) {
              raw->gate.run([this, raw, m] { onBlock(*raw, asInput(*m, m->point_count)); });
            }));
  }
  ROS_INFO("virtual_sensor: %zu sensor(s) at %.0f Hz, metrics every %lu samples", sensors_.size(),
           config_.sample_rate_hz, static_cast<unsigned long>(metrics_every_));
}

void VirtualSensorNode::onLayout(Source& source, const railvib::PointLayout& layout) {
  if (source.gate.isOpen()) return;
  status_->guard([&] {
    std::vector<double> xyz;
    for (const auto& p : layout.positions) xyz.insert(xyz.end(), {p.x, p.y, p.z});
    validatePointLayout(source.layout_sub.getTopic(), layout.names, layout.positions.size(), xyz, limits_.max_points);
    source.point_names = layout.names;
    for (auto& s : sensors_) {
      if (s.setup.source != source.name) continue;
      const auto it = std::find(layout.names.begin(), layout.names.end(), s.setup.point);
      if (it == layout.names.end()) {
        throw std::runtime_error("sensor " + s.setup.spec.name + ": point '" + s.setup.point + "' is not among the " +
                                 source.name + " output points");
      }
      s.point_index = static_cast<int>(it - layout.names.begin());
    }
    source.gate.open();
  });
}

void VirtualSensorNode::restartPass(Source& source) {
  source.ended = false;
  source.tracker = std::make_unique<SampleIndexTracker>(source.name);
  for (auto& s : sensors_) {
    if (s.setup.source != source.name) continue;
    s.sensor.reset();
    s.pending.clear();
    s.published = 0;
    s.latest_time_s = -1.0;
  }
  clock_s_ = -1.0;
  finished_ = false;
  next_block_index_ = 0;
}

void VirtualSensorNode::onBlock(Source& source, const InputBlock& block) {
  if (status_->failed()) return;
  // A looping replay restarts the stream: start a new pass of this source's sensors.
  if (source.ended && block.first_sample_index == 0) restartPass(source);
  if (finished_) return;
  status_->guard([&] {
    if (!source.gate.isOpen()) throw std::runtime_error(source.name + " data arrived before its point layout");
    // Period, counts and values against the config and the layout, before any index is used.
    BlockContract contract;
    contract.stream = source.data_sub.getTopic();
    contract.sample_period_s = 1.0 / input_rate_hz_;
    contract.period_source = "soil.output.receiver_rate_hz = " + formatValue(input_rate_hz_) + " Hz";
    contract.count_field = source.count_field;
    contract.point_label = "point";
    contract.point_count = static_cast<uint32_t>(source.point_names.size());
    contract.point_source = source.layout_name;
    contract.max_block_samples = limits_.max_block_samples;
    validateBlock(
        contract,
        {block.first_sample_index, block.end_of_stream, block.sample_period_s, block.sample_count, block.point_count},
        {{"velocity_m_s", block.velocity_m_s, 3, limits_.velocity_m_s, "limits.velocity_m_s", "m/s"}});
    source.tracker->accept(block.first_sample_index, block.sample_count);
    const double input_rate = input_rate_hz_;
    std::vector<double> frames(3 * block.sample_count);
    for (auto& s : sensors_) {
      if (s.setup.source != source.name) continue;
      if (!s.sensor) {
        s.setup.spec.input_rate_hz = input_rate;
        s.sensor = std::make_unique<signal::VirtualSensor>(s.setup.spec, 0.0);
      }
      for (uint32_t k = 0; k < block.sample_count; ++k) {
        for (int c = 0; c < 3; ++c) {
          frames[3 * k + c] =
              (*block.velocity_m_s)[(static_cast<size_t>(k) * block.point_count + s.point_index) * 3 + c];
        }
      }
      s.fresh.clear();
      s.sensor->push(frames.data(), block.sample_count, s.fresh);
      if (block.end_of_stream) s.sensor->flush(s.fresh);
      if (!s.fresh.empty()) s.latest_time_s = s.fresh.back().time_s;
    }
    // The clock first, so that when these samples go out, now >= their stamps (a subscriber to both
    // topics may still handle them in either order: ROS orders messages within a topic only).
    publishClock();
    for (auto& s : sensors_) {
      if (s.setup.source != source.name) continue;
      publishSamples(s, s.fresh, 0);
      // Final metrics of the whole record, whatever the cadence.
      if (block.end_of_stream && !s.fresh.empty() && s.published % metrics_every_ != 0) {
        publishMetrics(s, s.fresh.back().time_s);
      }
    }
    const double t_s = static_cast<double>(block.first_sample_index + block.sample_count) * block.sample_period_s;
    status_->countSamples(source.name + " in", block.sample_count);
    status_->update(t_s);
    if (block.end_of_stream) source.ended = true;
    const bool all_ended =
        std::all_of(sources_.begin(), sources_.end(), [](const std::unique_ptr<Source>& s) { return s->ended; });
    publishBlocks(all_ended);
    if (all_ended) {
      finished_ = true;
      status_->finish(t_s);
    }
  });
}

void VirtualSensorNode::publishClock() {
  if (!clock_publisher_) return;
  // The newest sample of any sensor: every sample published so far has a stamp <= now (a tool's delay,
  // now - stamp, is not negative when the sample goes out); a sensor fed later in the chain (the house)
  // shows its lag.
  double t_s = -1.0;
  for (const auto& s : sensors_) t_s = std::max(t_s, s.latest_time_s);
  if (!(t_s > clock_s_)) return;  // no sample yet, or no progress
  clock_s_ = t_s;
  rosgraph_msgs::Clock clock;
  clock.clock = ros::Time(t_s);
  clock_publisher_.publish(clock);
}

void VirtualSensorNode::publishSamples(Sensor& s, const std::vector<signal::SensorSample>& samples, size_t from) {
  const std::string frame = names::sensorFrame(s.setup.spec.name);
  const double g = config_.include_gravity ? kGravity_m_s2 : 0.0;
  const double noise_var = s.setup.spec.noise_rms_m_s2 * s.setup.spec.noise_rms_m_s2;
  for (size_t i = from; i < samples.size(); ++i) {
    const auto& x = samples[i];
    const ros::Time stamp(x.time_s);
    sensor_msgs::Imu imu;
    imu.header.stamp = stamp;
    imu.header.frame_id = frame;
    imu.orientation_covariance[0] = -1.0;       // no orientation estimate (sensor_msgs/Imu rule)
    imu.angular_velocity_covariance[0] = -1.0;  // no gyroscope
    imu.linear_acceleration.x = x.acceleration_m_s2[0];
    imu.linear_acceleration.y = x.acceleration_m_s2[1];
    imu.linear_acceleration.z = x.acceleration_m_s2[2] + g;
    // Diagonal noise variance; all zeros means "unknown" per the message, used for a perfect sensor.
    imu.linear_acceleration_covariance[0] = imu.linear_acceleration_covariance[4] =
        imu.linear_acceleration_covariance[8] = noise_var;
    s.imu.publish(imu);
    geometry_msgs::Vector3Stamped v;
    v.header = imu.header;
    v.vector.x = x.velocity_m_s[0];
    v.vector.y = x.velocity_m_s[1];
    v.vector.z = x.velocity_m_s[2];
    s.velocity.publish(v);
    s.pending.push_back(x);
    ++s.published;
    if (s.published % metrics_every_ == 0) publishMetrics(s, x.time_s);
  }
}

void VirtualSensorNode::publishMetrics(Sensor& s, double time_s) {
  const signal::MonitorSnapshot m = s.sensor->metrics();
  // The standards that apply where the sensor stands, judged up to the soil's resolved frequency.
  const signal::SensorVerdict verdict = signal::sensorVerdict(
      m, config_.night ? signal::Din4150_2Period::Night : signal::Din4150_2Period::Day, s.setup.kind, resolved_hz_);
  const signal::PpvComponent& governing = verdict.din4150_3.governing;
  railvib::VibrationMetrics msg;
  msg.header.stamp = ros::Time(time_s);
  msg.header.frame_id = names::sensorFrame(s.setup.spec.name);
  msg.sensor_name = s.setup.spec.name;
  msg.kind = static_cast<uint8_t>(s.setup.kind);
  msg.resolved_hz = resolved_hz_;
  msg.kb_f = m.kb_f.empty() ? 0.0 : *std::max_element(m.kb_f.begin(), m.kb_f.end());
  msg.kb_f_max = m.kb_fmax_all;
  msg.ppv_m_s = m.ppv.vector_peak_mm_s * 1e-3;
  msg.ppv_vertical_m_s = m.ppv.components.size() > 2 ? m.ppv.components[2].ppv_mm_s * 1e-3 : 0.0;
  msg.governing_component = static_cast<uint8_t>(verdict.din4150_3.governing_component);
  msg.governing_ppv_m_s = governing.ppv_mm_s * 1e-3;
  msg.dominant_frequency_hz = governing.frequency_hz;
  msg.din4150_3_limit_m_s = governing.limit_mm_s * 1e-3;
  for (size_t b = 0; b < m.bands.size(); ++b) {
    msg.third_octave_center_hz.push_back(m.bands[b].nominal_hz);
    msg.third_octave_level_db.push_back(m.third_octave_running_db.size() > 2 ? m.third_octave_running_db[2][b] : 0.0);
  }
  msg.din4150_2_verdict = static_cast<uint8_t>(verdict.din4150_2.level);
  msg.din4150_2_a_u = verdict.din4150_2.guide.a_u;
  msg.din4150_2_a_o = verdict.din4150_2.guide.a_o;
  msg.din4150_2_a_r = verdict.din4150_2.guide.a_r;
  msg.din4150_3_verdict = static_cast<uint8_t>(verdict.din4150_3.level);
  msg.verdict = static_cast<uint8_t>(verdict.level);
  s.metrics.publish(msg);
  all_metrics_publisher_.publish(msg);

  diagnostic_msgs::DiagnosticArray diag;
  diag.header.stamp = msg.header.stamp;
  diagnostic_msgs::DiagnosticStatus status;
  status.name = "railvib/virtual_sensor/" + s.setup.spec.name;
  status.hardware_id = msg.header.frame_id;
  // VerdictLevel's OK, WARN, ERROR are diagnostic_msgs/DiagnosticStatus's; a standard that does not apply
  // is OK, one the model cannot judge a warning.
  if (verdict.level == Level::NotApplicable) {
    status.level = diagnostic_msgs::DiagnosticStatus::OK;
  } else if (verdict.level == Level::NotAssessable) {
    status.level = diagnostic_msgs::DiagnosticStatus::WARN;
  } else {
    status.level = msg.verdict;
  }
  status.message = verdict.reason;
  auto kv = [&](const std::string& k, double v) {
    diagnostic_msgs::KeyValue p;
    p.key = k;
    p.value = std::to_string(v);
    status.values.push_back(p);
  };
  kv("KB_F", msg.kb_f);
  kv("KB_Fmax", msg.kb_f_max);
  kv("PPV [mm/s]", msg.ppv_m_s * 1e3);
  kv("dominant frequency [Hz]", msg.dominant_frequency_hz);
  kv("samples", static_cast<double>(s.published));
  diag.status.push_back(status);
  diagnostics_publisher_.publish(diag);
}

void VirtualSensorNode::publishBlocks(bool end_of_stream) {
  size_t ready = sensors_.front().pending.size();
  for (const auto& s : sensors_) ready = std::min(ready, s.pending.size());
  const size_t consumed =
      splitIntoBlocks(ready, block_samples_, end_of_stream, [&](size_t offset, size_t count, bool last) {
        railvib::SensorSamples block;
        block.header.stamp = ros::Time(static_cast<double>(next_block_index_) / config_.sample_rate_hz);
        block.header.frame_id = names::kTrackFrame;
        block.first_sample_index = next_block_index_;
        block.end_of_stream = last;
        block.sample_period_s = 1.0 / config_.sample_rate_hz;
        block.sample_count = static_cast<uint32_t>(count);
        block.sensor_count = static_cast<uint32_t>(sensors_.size());
        for (const auto& s : sensors_) block.sensor_names.push_back(s.setup.spec.name);
        for (size_t k = offset; k < offset + count; ++k) {
          for (const auto& s : sensors_) {
            const signal::SensorSample& x = s.pending[k];
            block.velocity_m_s.insert(block.velocity_m_s.end(), x.velocity_m_s, x.velocity_m_s + 3);
            block.acceleration_m_s2.insert(block.acceleration_m_s2.end(), x.acceleration_m_s2, x.acceleration_m_s2 + 3);
          }
        }
        samples_publisher_.publish(block);
        status_->countSamples("sensor_samples out", count);
        next_block_index_ += count;
      });
  for (auto& s : sensors_) s.pending.erase(s.pending.begin(), s.pending.begin() + static_cast<long>(consumed));
}

}  // namespace railvib::ros_io
