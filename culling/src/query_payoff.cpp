#include "forest/culling/query_payoff.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "forest/core/error.hpp"

namespace forest::culling {
namespace {
constexpr std::uint64_t kForgetAfterFrames = 64;

bool usesQueries(CullingStrategy s) { return s != CullingStrategy::None && s != CullingStrategy::Frustum; }
}  // namespace

QueryPayoff::QueryPayoff(QueryPayoffSettings settings) : settings_(settings) {
  const QueryPayoffSettings& s = settings_;
  auto require = [](bool ok, const char* what, double value, const char* expected) {
    if (!ok) throw Error(fmt::format("QueryPayoff: {} = {}, expected {}", what, value, expected));
  };
  require(s.window >= 1, "window", s.window, "at least 1");
  require(s.probeFrames >= 1, "probeFrames", s.probeFrames, "at least 1");
  require(s.firstProbe >= 1, "firstProbe", s.firstProbe, "at least 1");
  require(s.maxProbeInterval >= s.firstProbe, "maxProbeInterval", s.maxProbeInterval, "at least firstProbe");
  require(s.margin >= 0.0 && s.margin < 1.0, "margin", s.margin, "in [0, 1)");
  reset();
}

void QueryPayoff::reset() {
  nextFrame_ = 0;
  fallenBack_ = false;
  probeLeft_ = probeOutstanding_ = 0;
  probeTimes_.clear();
  interval_ = settings_.firstProbe;
  nextProbeAt_ = static_cast<std::uint64_t>(settings_.firstProbe);
  recent_.clear();
  otherCost_ = -1.0;
  planned_.clear();
  switches_ = probes_ = 0;
}

double QueryPayoff::median(const std::vector<double>& values) const {
  std::vector<double> v = values;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

CullingStrategy QueryPayoff::next(std::uint64_t frame, CullingStrategy asked) {
  if (frame < nextFrame_) throw Error(fmt::format("QueryPayoff: frame {} after frame {}", frame, nextFrame_ - 1));
  nextFrame_ = frame + 1;
  if (!usesQueries(asked)) return asked;
  // Frames never recorded (a timer that dropped them) are forgotten; a probe goes on without them.
  while (!planned_.empty() && planned_.front().frame + kForgetAfterFrames < frame) {
    if (planned_.front().probe && --probeOutstanding_ == 0 && probeLeft_ == 0) finishProbe();
    planned_.pop_front();
  }
  if (probeLeft_ == 0 && probeOutstanding_ == 0 && frame >= nextProbeAt_) {
    probeLeft_ = settings_.probeFrames;
    probeTimes_.clear();
    ++probes_;
  }
  const bool probe = probeLeft_ > 0;
  const bool frustum = probe ? !fallenBack_ : fallenBack_;
  if (probe) {
    --probeLeft_;
    ++probeOutstanding_;
  }
  planned_.push_back({frame, frustum, probe});
  return frustum ? CullingStrategy::Frustum : asked;
}

void QueryPayoff::record(std::uint64_t frame, double milliseconds) {
  const auto it = std::find_if(planned_.begin(), planned_.end(), [frame](const Planned& p) { return p.frame == frame; });
  if (it == planned_.end()) return;
  const Planned p = *it;
  planned_.erase(it);
  const bool measured = std::isfinite(milliseconds) && milliseconds >= 0.0;
  if (p.probe) {
    if (measured) probeTimes_.push_back(milliseconds);
    if (--probeOutstanding_ == 0 && probeLeft_ == 0) finishProbe();
    return;
  }
  if (!measured || p.frustum != fallenBack_) return;  // a frame of the way left since
  recent_.push_back(milliseconds);
  if (static_cast<int>(recent_.size()) > settings_.window) recent_.erase(recent_.begin());
  // The view changed: the current way now costs more than the other did when last measured.
  const bool full = static_cast<int>(recent_.size()) == settings_.window;
  if (full && otherCost_ >= 0.0 && probeLeft_ == 0 && probeOutstanding_ == 0 &&
      otherCost_ * (1.0 + settings_.margin) < median(recent_))
    nextProbeAt_ = nextFrame_;
}

void QueryPayoff::finishProbe() {
  if (!probeTimes_.empty() && !recent_.empty()) {
    const double probe = median(probeTimes_), current = median(recent_);
    if (probe * (1.0 + settings_.margin) < current) {  // the other way is cheaper by the margin: switch
      fallenBack_ = !fallenBack_;
      otherCost_ = current;
      recent_ = probeTimes_;
      if (static_cast<int>(recent_.size()) > settings_.window)
        recent_.erase(recent_.begin(), recent_.end() - settings_.window);
      interval_ = settings_.firstProbe;
      ++switches_;
    } else {
      // A way that lost by a factor k waits 2k times as long for its next probe.
      otherCost_ = probe;
      const double loss = current > 0.0 ? std::max(1.0, probe / current) : 1.0;
      interval_ = static_cast<int>(std::min(2.0 * interval_ * loss, static_cast<double>(settings_.maxProbeInterval)));
    }
  } else if (!probeTimes_.empty()) {
    otherCost_ = median(probeTimes_);  // nothing of the current way measured yet: ask again later
  }
  probeTimes_.clear();
  nextProbeAt_ = nextFrame_ + static_cast<std::uint64_t>(interval_);
}

}  // namespace forest::culling
