#pragma once
// Pass 2 of the frame (DESIGN §1, thesis §9.2): from the visible set to the light — the focus body
// B of the visible receivers up to z_f, the shadow setup of the chosen method (n smoothed over
// time, §9.2.5), and the casters the shadow pass draws. CPU only.
#include <cstdint>
#include <vector>

#include "forest/culling/occlusion_culler.hpp"
#include "forest/render/frame.hpp"
#include "forest/render/scene_objects.hpp"
#include "forest/shadows/casters.hpp"
#include "forest/shadows/shadow_setup.hpp"

namespace forest::render {

// What the shadow pass and the shadow term work from. Kept from the last frame that had a sun and
// receivers.
struct ShadowPlan {
  bool shadowed = false;               // sun up, something visible: the map is drawn
  shadows::ShadowSetup setup;
  std::vector<std::uint32_t> casters;  // object indices
  Camera camera;                       // the eye camera with far = z_f (what B was built from)
};

class ShadowSetupPass {
 public:
  // Fills `plan` (and the shadow statistics) for this frame's visible set. `l`: the unit light
  // direction; `sceneBounds`: S.
  void run(const Camera& camera, const culling::CullingResult& visible, const FrameSettings& settings,
           const glm::dvec3& l, bool sunBelowHorizon, const SceneObjects& objects, const Aabb& sceneBounds,
           ShadowPlan& plan, FrameStats& stats);
  // Forgets the smoothed n and the stable map's radius (a camera cut).
  void reset() {
    previousN_ = 0.0;
    stableRadius_ = 0.0;
  }

 private:
  // Casters of the visible receivers (DESIGN §4): each receiver's part inside the view, grown by
  // the filter's footprint, swept along the light (shadows::CasterSelector).
  void selectCastersOfReceivers(const Camera& shadowCamera, const shadows::ShadowSetup& setup, const FrameSettings& settings,
                                const glm::dvec3& l, const SceneObjects& objects, const Aabb& sceneBounds,
                                std::vector<std::uint32_t>& casters);

  double previousN_ = 0.0;     // lispsm: the last frame's n (ShadowInput::previousN); 0: none
  double stableRadius_ = 0.0;  // uniform-stable: the last map radius (ShadowInput::previousStableRadius)
  // Kept from frame to frame, so a steady-state frame allocates nothing (DESIGN §9).
  std::vector<Aabb> receivers_, footprints_;
  shadows::CasterSelector selector_;
};

}  // namespace forest::render
