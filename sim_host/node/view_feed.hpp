#pragma once
// What a live view (view/live_view.hpp) is fed from an estimator pipeline: its estimates, its map and its particle
// cloud, in the view's types. estimator_node and sim_host's runs share it. Host only.
#include "hal/estimate.hpp"
#include "node/estimator_pipeline.hpp"
#include "view/live_view.hpp"

namespace node {

view::EstimateSample view_sample(const hal::Estimate& e);
view::MapGrid view_map(const est::OccupancyGrid& g);
// The pipeline's particles (MCL), when the view wants a cloud (its rate, a subscriber).
void feed_particles(view::LiveView& v, const EstimatorPipeline& p, hal::TimeNs stamp_ns);

}  // namespace node
