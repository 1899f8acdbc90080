// A live view fed from an estimator pipeline (node/view_feed.hpp).
#include "node/view_feed.hpp"

namespace node {

view::EstimateSample view_sample(const hal::Estimate& e) {
  view::EstimateSample v;
  v.stamp_ns = e.stamp_ns;
  v.pose = {e.pose.x, e.pose.y, e.pose.theta};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) v.covariance[3 * r + k] = static_cast<double>(e.covariance(r, k));
  v.status = e.status;
  v.rejected_inputs = e.rejected_inputs;
  return v;
}

view::MapGrid view_map(const est::OccupancyGrid& g) {
  view::MapGrid m;
  m.width = g.width();
  m.height = g.height();
  m.resolution_m = static_cast<double>(g.resolution());
  m.origin_x = static_cast<double>(g.origin_x());
  m.origin_y = static_cast<double>(g.origin_y());
  m.cells.assign(g.cells(), g.cells() + g.cell_count());
  return m;
}

void feed_particles(view::LiveView& v, const EstimatorPipeline& p, hal::TimeNs stamp_ns) {
  if (!v.particles_due()) return;
  const est::ConstParticleSetView c = p.particles();
  if (c.count > 0) v.publish_particles(stamp_ns, c.x, c.y, c.theta, c.count);
}

}  // namespace node
