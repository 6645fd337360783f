// Field sources: anything that gives the magnet's flux density B (tesla) at a
// point in the magnet frame (mm). The probe-path layers only see this.
#pragma once
#include <Eigen/Core>
#include <array>
#include <memory>
#include <optional>
#include <string>

namespace magenc {

using Vec3 = Eigen::Vector3d;
struct Magnet;

class FieldSource {
 public:
  virtual ~FieldSource() = default;
  // Short identifier written into tables: "linear", "analytic", "grid", "fem".
  virtual std::string name() const = 0;
  // B [T] at p_mm (magnet frame, mm). Throws InputError when p lies outside
  // the region the source can serve (never extrapolates silently).
  virtual Vec3 B_T(const Vec3& p_mm) const = 0;
  // True when the source knows the full vector B in a 3-D region, so that it
  // can serve tilted probes (sensor or magnet tilt: positions off the sensing
  // plane, normals off z). False for sources that only know Bz on a plane (a
  // 2-D grid, the linear model Bz = k*x).
  virtual bool gives_full_vector() const { return true; }
  // Bz only; sources may override with a cheaper kernel.
  virtual double Bz_T(const Vec3& p_mm) const { return B_T(p_mm).z(); }
  // Batch evaluation: p_mm is 3xN (mm), returns 3xN (T). Parallel (OpenMP).
  virtual Eigen::Matrix3Xd B_T(const Eigen::Matrix3Xd& p_mm) const;
  // Batch Bz: p_mm 3xN -> N values (T). Parallel (OpenMP).
  virtual Eigen::VectorXd Bz_T(const Eigen::Matrix3Xd& p_mm) const;
  // The magnet when this source is its exact field (the body is known: paths may be checked against it,
  // the magnetization varied), else nullptr.
  virtual const Magnet* exact_magnet() const { return nullptr; }

  // Rotational symmetry about the z axis. A source whose body is axisymmetric about z and whose B is
  // linear in the magnetization M = M0 m (the exact cylinder) returns m (unit) and the fields B_k of
  // the same body magnetized along axis k with |M| = M0, so that B(p) = sum_k m_k B_k(p) and, for
  // every angle a, B(Rz(a) p; M) = Rz(a) B(p; Rz(-a) M). A grid, a table, a FEM solve or the linear
  // model is one fixed sample of a field and has no such parts: nullopt (the default).
  struct AxisymmetricParts {
    Vec3 m = Vec3::UnitX();
    std::array<std::shared_ptr<const FieldSource>, 3> along_axis;  // B_x, B_y, B_z
  };
  virtual std::optional<AxisymmetricParts> axisymmetric_parts() const { return std::nullopt; }
};

using FieldSourcePtr = std::shared_ptr<const FieldSource>;

}  // namespace magenc
