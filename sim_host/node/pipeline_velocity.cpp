// The estimator pipelines of the velocity model (node/estimator_pipeline_impl.hpp), one translation unit per model.
#include "node/estimator_pipeline_impl.hpp"

namespace node::detail {
template std::unique_ptr<EstimatorPipeline> make_for_model<est::VelocityMotionModel>(const EstimatorSpec&, const EstimatorMaps&,
                                                                      hal::Clock&, hal::Clock&, hal::EstimateSink&);
}  // namespace node::detail
