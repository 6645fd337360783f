#include "fields/field_source.hpp"

#include <exception>
#include <mutex>

namespace magenc {

namespace {
// Runs f(i) for i in [0, n) on all threads; rethrows the first exception.
template <class F>
void parallel_for(Eigen::Index n, F&& f) {
  std::exception_ptr err;
  std::mutex m;
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) {
    try {
      f(i);
    } catch (...) {
      std::lock_guard<std::mutex> lock(m);
      if (!err) err = std::current_exception();
    }
  }
  if (err) std::rethrow_exception(err);
}
}  // namespace

Eigen::Matrix3Xd FieldSource::B_T(const Eigen::Matrix3Xd& p_mm) const {
  Eigen::Matrix3Xd out(3, p_mm.cols());
  parallel_for(p_mm.cols(), [&](Eigen::Index i) { out.col(i) = B_T(Vec3(p_mm.col(i))); });
  return out;
}

Eigen::VectorXd FieldSource::Bz_T(const Eigen::Matrix3Xd& p_mm) const {
  Eigen::VectorXd out(p_mm.cols());
  parallel_for(p_mm.cols(), [&](Eigen::Index i) { out[i] = Bz_T(Vec3(p_mm.col(i))); });
  return out;
}

}  // namespace magenc
