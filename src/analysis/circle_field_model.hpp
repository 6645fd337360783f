// CircleFieldModel: local polynomial models of the field around N nodes on a circle in a
// plane z = const (the surrogate of the radius scan, analysis/radius_scan.hpp: why and how).
#pragma once
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fields/field_source.hpp"

namespace magenc {

// Local polynomial models of Bz around N nodes on a circle (see above).
class CircleFieldModel {
 public:
  // field: the source; r0_mm: circle radius; plane_z_mm: its height (magnet
  // frame); nodes: N; reach_xy_mm / reach_z_mm: largest in-plane / vertical
  // displacement the model must serve (floored at 0.01 mm); order: total
  // polynomial degree 2..4. Stencil: 5 x 5 x 5 points spanning +-reach.
  // full_vector: also fit Bx and By (needed for tilted mounts: the probes
  // then read n.B; the field must give the full vector).
  //
  // How the node models are built (`how`):
  //  axis_aligned: every node's stencil along the magnet frame's axes, one fit per node (N x 125
  //    field evaluations); any source.
  //  rotated: every node's stencil turned with the node (node j's = node 0's rotated by 2 pi j/N about
  //    z), one fit per node; the reference that `symmetry` must equal.
  //  symmetry: a source with FieldSource::axisymmetric_parts() only: node 0's stencil is sampled once
  //    per magnetization axis the field needs (2, or 3 with an axial part: 250 or 375 evaluations in
  //    all) and every node follows from B(Rz(a) p; M) = Rz(a) B(p; Rz(-a) M) and B linear in M. Equal
  //    to `rotated` up to round-off (the least-squares fit is linear and commutes with the rotation).
  //  symmetrized: any source whose body is axisymmetric but whose field is not exactly so (an FE solution:
  //    its mesh breaks the symmetry at the discretization level). Node 0's turned stencil is sampled at
  //    kSymmetrizedAzimuths = 12 azimuths a_l = 360 l / 12 deg (1,500 evaluations), each turned back into
  //    node 0's frame; their least-squares parts cos(a) P + sin(a) Q + Z (the first angular harmonic and
  //    the mean over the azimuths) are fitted once and give every node as in `symmetry`. The model's
  //    coefficients are this symmetric part; the field at every node (N more evaluations) minus it is
  //    kept as node_residual (the asymmetry at the nodes: an FE mesh's artefact harmonics), which the
  //    pipeline adds to each reading at the nominal node (FastPipeline). So an ideal mount reads the
  //    field exactly at the nodes, as with direct fits; what is left out is how the asymmetry changes
  //    with the displacement. 12 azimuths: a mesh of D_N symmetry (N = 16 by default) has, besides the
  //    cos part, the angular harmonics kN +- 1, and with 12 azimuths none of 15, 17, 31, 33 folds onto
  //    the first harmonic.
  //  automatic: symmetry when the source declares it, else symmetrized when its node residual stays
  //    within kSymmetrizedMaxResidual of the first-harmonic amplitude, else axis_aligned.
  // The constructor's default is axis_aligned; the radius and design studies take automatic (keys
  // radius.surrogate_build, design.surrogate_build). `symmetry` differs from direct fits at the
  // fit-residual level (measured on the default radius scan: p99 by up to 6.4e-4 deg, inside the Monte
  // Carlo's own error of ~4e-3 deg, but enough to move diff4's flat minimum from r0 = 2.50 to 2.45 mm,
  // whose totals differ by 2e-5 deg).
  // Every node's coefficients are in the magnet frame's displacement (a turned stencil's fit is
  // re-expanded: a rotated polynomial of degree <= order is again one).
  enum class Construction { automatic, axis_aligned, rotated, symmetry, symmetrized };
  static constexpr int kSymmetrizedAzimuths = 12;
  static constexpr double kSymmetrizedMaxResidual = 1e-4;  // relative to amplitude_T() (automatic's test)
  CircleFieldModel(const FieldSource& field, double r0_mm, double plane_z_mm, int nodes, double reach_xy_mm,
                   double reach_z_mm, int order = 4, bool full_vector = false,
                   Construction how = Construction::axis_aligned);
  Construction construction() const { return construction_; }
  // "automatic", "axis_aligned", "rotated", "symmetry" or "symmetrized" (the keys' spelling).
  static Construction construction_named(const std::string& name);
  static std::string construction_name(Construction how);  // the inverse
  // Field evaluations the construction took (points; a full-vector point counts once).
  long field_evaluations() const { return field_evaluations_; }

  int nodes() const { return nodes_; }
  int terms() const { return static_cast<int>(exps_.size()); }
  double r0_mm() const { return r0_mm_; }
  double plane_z_mm() const { return plane_z_mm_; }
  bool full_vector() const { return coef_x_.size() > 0; }
  // Model B (T, 3 components) at node j displaced by the displacement whose monomials are u (full_vector only).
  void B_T(int node, const double* u, double* B) const {
    const Eigen::Map<const Eigen::VectorXd> uu(u, terms());
    B[0] = coef_x_.col(node).dot(uu);
    B[1] = coef_y_.col(node).dot(uu);
    B[2] = coef_.col(node).dot(uu);
  }
  // n . B (T) at node j displaced by the displacement whose monomials are u (full_vector models): one
  // vectorized pass over the three components' coefficients.
  double Bn_T(int node, const double* u, double nx, double ny, double nz) const {
    const Eigen::Map<const Eigen::VectorXd> uu(u, terms());
    return (nx * coef_x_.col(node) + ny * coef_y_.col(node) + nz * coef_.col(node)).dot(uu);
  }
  double reach_xy_mm() const { return reach_xy_mm_; }
  double reach_z_mm() const { return reach_z_mm_; }
  // Monomials of a displacement (magnet frame, mm): u must hold terms() values.
  void monomials(double ex_mm, double ey_mm, double ez_mm, double* u) const;
  // The same of a displacement already divided by the reach (ux = ex / reach_xy, ...).
  void scaled_monomials(double ux, double uy, double uz, double* u) const;
  // Model Bz (T) at node j displaced by the displacement whose monomials are u.
  double bz_T(int node, const double* u) const { return coef_.col(node).dot(Eigen::Map<const Eigen::VectorXd>(u, terms())); }
  // Bz sampled exactly at node j (no displacement), T.
  double node_bz_T(int node) const { return center_T_[node]; }
  // Amplitude of the first angular harmonic of Bz on the circle (T).
  double amplitude_T() const { return amplitude_T_; }
  // Largest |fit - sample| over every stencil point and node (T): a fit diagnostic.
  double fit_residual_T() const { return fit_residual_T_; }
  // symmetrized models: the field at node j minus the model's (symmetric part's) value there, component
  // c = 0 (Bz), 1 (Bx), 2 (By; full_vector only), T; 0 for the other constructions. node_bz_T() is the
  // field's own value at the node (the symmetric part plus this).
  bool has_node_residual() const { return node_residual_.size() > 0; }
  double node_residual_T(int c, int node) const { return node_residual_(c, node); }
  double node_residual_max_T() const { return node_residual_max_T_; }

 private:
  struct StencilFit;  // the constrained least-squares fit on the stencil (circle_field_model.cpp)
  // Every step of the construction `how` (not automatic) into this model.
  void build(const FieldSource& field, const std::optional<FieldSource::AxisymmetricParts>& parts, bool full_vector,
             Construction how);
  // The symmetrized construction's fits of every node from the samples S (rows Bz (, Bx, By); columns:
  // node 0's stencil at each of the kSymmetrizedAzimuths azimuths).
  std::vector<Eigen::MatrixXd> symmetrized_fits(const Eigen::MatrixXd& S, const StencilFit& fit, bool full_vector,
                                                const std::vector<double>& cphi, const std::vector<double>& sphi);
  // symmetrized: node_residual_ (the field at every node minus the model there) and center_T_.
  void node_residuals(const FieldSource& field, bool full_vector, const std::vector<double>& cphi,
                      const std::vector<double>& sphi);
  // Node j's fits G[c].col(j) = Rz(phi_j) sum_k w_k F[k] (weights(j, w)), fit_residual_T_ from R likewise.
  std::vector<Eigen::MatrixXd> combine_parts(const std::array<Eigen::MatrixXd, 3>& F,
                                             const std::array<Eigen::MatrixXd, 3>& R, bool full_vector,
                                             const std::vector<double>& cphi, const std::vector<double>& sphi,
                                             const std::function<void(int, double*)>& weights);
  // Monomials of every stencil point (rows) after turning it by (c, s) = (cos, sin) of -phi: P x terms.
  Eigen::MatrixXd stencil_monomials(const std::vector<Eigen::Vector3d>& stencil, double c, double s) const;
  // Field samples at pts: rows Bz (then Bx, By with full_vector) x points; counts the evaluations.
  Eigen::MatrixXd sample(const FieldSource& src, const Eigen::Matrix3Xd& pts, bool full_vector,
                         const std::string& field_name);
  // The symmetry construction's fits of every node from node 0's stencil points pts0.
  std::vector<Eigen::MatrixXd> symmetry_fits(const FieldSource::AxisymmetricParts& parts, const Eigen::Matrix3Xd& pts0,
                                             const StencilFit& fit, bool full_vector,
                                             const std::string& field_name, const std::vector<double>& cphi,
                                             const std::vector<double>& sphi);
  // Turned stencils' fits G (stencil coordinates) -> coef_, coef_x_, coef_y_ (frame coordinates).
  void to_frame_coefficients(const std::vector<Eigen::Vector3d>& stencil, const std::vector<Eigen::MatrixXd>& G,
                             const std::vector<double>& cphi, const std::vector<double>& sphi);

  int nodes_ = 0;
  int order_ = 4;
  double r0_mm_ = 0, plane_z_mm_ = 0, reach_xy_mm_ = 0, reach_z_mm_ = 0;
  std::vector<std::array<int, 3>> exps_;  // exponents (a, b, c) of u_x^a u_y^b u_z^c
  Eigen::MatrixXd coef_;                  // terms x nodes: fit coefficients of Bz per node (T)
  Eigen::MatrixXd coef_x_, coef_y_;       // the same for Bx, By (empty unless full_vector)
  Eigen::VectorXd center_T_;              // exact Bz at the nodes (T)
  double amplitude_T_ = 0;
  double fit_residual_T_ = 0;
  Construction construction_ = Construction::axis_aligned;
  long field_evaluations_ = 0;
  Eigen::MatrixXd node_residual_;          // components x nodes (symmetrized only)
  double node_residual_max_T_ = 0;
};

}  // namespace magenc
