// A finite-element solution psi with everything needed to evaluate B at any
// point: dof nodes, cells, per-cell material; plus fast point location.
#pragma once
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "fields/analytic_field.hpp"

namespace magenc::fem {

struct FeSolution {
  int order = 1;                 // Lagrange order (1 or 2)
  Eigen::Matrix3Xd points_mm;    // 3 x num_dofs dof nodes (mm): vertices, P2 edge midpoints
  Eigen::MatrixXi cell_dofs;     // (4|10) x n_cells dof ids, VTK order (first 4 = vertices)
  Eigen::VectorXd psi_Tmm;       // num_dofs scalar potential psi = mu0*phi_m (T*mm)
  Eigen::VectorXi region;        // n_cells region ids (mesh.hpp)
  Eigen::VectorXd mu_r;          // n_cells relative permeability
  Eigen::Matrix3Xd br_T;         // 3 x n_cells remanence vector Br = mu0*M0 (T), 0 outside magnets
  // Reduced potential (fem.potential = reduced): psi_Tmm is the reaction
  // potential phi and the magnet's free-space field is added analytically:
  //   B = mu_r (H_s - grad phi) + Br_s,  H_s = B_exact - Br_s,
  // Br_s = the source's remanence inside its (true, round) cylinder, 0
  // outside; br_T is then not used for B. Null: total potential.
  std::shared_ptr<const AnalyticField> source;
  // Split potential (fem.potential = split, reduced_potential.hpp): with a
  // source, cells with cell_total[c] = 1 (the shaft) carry the total potential
  // psi (B = mu_r (-grad psi) + Br), the others the reduced phi = psi_Tmm -
  // interface_phi_s (phi_s at the interface dofs, 0 elsewhere). Both empty:
  // one potential in every cell.
  std::vector<char> cell_total;
  Eigen::VectorXd interface_phi_s_Tmm;
  bool split() const { return !cell_total.empty(); }
  // The potential of cell c at its local dof i: psi_Tmm, minus phi_s at the
  // interface in the reduced cells of a split solution.
  double cell_dof_value(int c, int i) const {
    const int d = cell_dofs(i, c);
    return split() && !cell_total[static_cast<size_t>(c)] ? psi_Tmm[d] - interface_phi_s_Tmm[d] : psi_Tmm[d];
  }
  // Gradient recovery (optional): grad psi averaged at every dof node over the
  // cells around it, then interpolated with the same Lagrange basis. Used only
  // in cells whose dofs all lie inside one material (same mu_r and Br), so the
  // jump of grad psi at material interfaces is kept.
  Eigen::Matrix3Xd grad_recovered;      // 3 x num_dofs recovered grad psi (T); empty: off
  std::vector<char> cell_uses_recovery; // n_cells: 1 where the recovered gradient is used
  // Computes grad_recovered and cell_uses_recovery.
  void recover_gradient();

  int num_cells() const { return static_cast<int>(cell_dofs.cols()); }
  // B (T) in cell c at barycentric point L: mu_r*(-grad psi) + Br (recovered
  // gradient where available).
  Eigen::Vector3d B_in_cell(int c, const Eigen::Vector4d& L) const;
  // psi (T*mm) in cell c at barycentric point L (split: the cell's own potential, psi or phi).
  double psi_in_cell(int c, const Eigen::Vector4d& L) const;
};

// Reduced potential helpers: the source's remanence at x (Br inside its round
// cylinder, else 0), its free-space H (scaled, T) = B_exact - Br_s, and
// B = mu_r (H_s - grad phi) + Br_s.
Eigen::Vector3d source_remanence_T(const AnalyticField& source, const Eigen::Vector3d& x_mm);
Eigen::Vector3d source_H_T(const AnalyticField& source, const Eigen::Vector3d& x_mm);
Eigen::Vector3d reduced_B(const AnalyticField& source, double mu_r, const Eigen::Vector3d& x_mm,
                          const Eigen::Vector3d& grad_phi);

// Point location in a tetrahedral mesh. A start cell near p comes from a
// bucket grid of cell centroids that is refined where the cells are small: a
// uniform top grid (about 2 cells per bucket) and, inside every top bucket
// holding more than kRefineAbove cells, a nested grid over that bucket (again
// about 2 cells per bucket), so that on a graded mesh the start lies about one
// local cell size from p. A visibility walk across faces (neighbour opposite
// the most negative barycentric coordinate) then reaches a containing cell. A
// point on a shared face, edge or vertex (within the tolerance) is given to
// the lowest-numbered cell that contains it, so the hit does not depend on
// where the walk started (cold or warm start, thread count). O(n) memory.
class PointLocator {
 public:
  // nodes: 3 x n vertices (mm); tets: first 4 rows of cell_dofs (vertex ids).
  PointLocator(const Eigen::Matrix3Xd& nodes, const Eigen::MatrixXi& cells);
  struct Hit {
    int cell;
    Eigen::Vector4d L;  // barycentric coordinates in that cell
  };
  // The cell containing p (mm) within a tolerance, or nullopt outside the mesh.
  // start_cell >= 0: a warm start (e.g. the previous point's cell); a walk
  // that does not arrive within a few steps restarts from start_near(p).
  // cells_visited (optional): the number of cells whose barycentric
  // coordinates were computed.
  std::optional<Hit> locate(const Eigen::Vector3d& p_mm, int start_cell = -1, int* cells_visited = nullptr) const;
  // The cold start: a cell whose centroid lies in the (nested) bucket of p or the nearest non-empty one.
  int start_near(const Eigen::Vector3d& p_mm) const;
  int num_cells() const { return static_cast<int>(tets_.cols()); }
  // A barycentric coordinate >= kInsideTol counts as inside (p on a face, edge or vertex belongs to every cell there).
  static constexpr double kInsideTol = -1e-10;
  // Top buckets with more cells than this get a nested grid.
  static constexpr int kRefineAbove = 8;

 private:
  // A uniform grid of buckets over a box; CSR lists of the cells whose centroid lies in each bucket.
  struct BucketGrid {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), size = Eigen::Vector3d::Ones();
    Eigen::Vector3i dims = Eigen::Vector3i::Ones();
    std::vector<int> start, cells;
    // Grid over [lo, hi] with about 2 of the cells `ids` (centroids cen) per bucket, at most max_dim per axis.
    void build(const Eigen::Matrix3Xd& cen, const std::vector<int>& ids, const Eigen::Vector3d& lo,
               const Eigen::Vector3d& hi, int max_dim);
    Eigen::Vector3i index_of(const Eigen::Vector3d& p) const;  // clamped to the grid
    long bucket(const Eigen::Vector3i& ijk) const { return (static_cast<long>(ijk[2]) * dims[1] + ijk[1]) * dims[0] + ijk[0]; }
    // The first cell of p's bucket, else of the nearest non-empty bucket (growing shells); -1 if empty.
    int first_near(const Eigen::Vector3d& p) const;
  };
  enum class Walk { found, outside, gave_up };
  Walk walk(const Eigen::Vector3d& p, int t, int max_steps, Hit& hit, int& visited) const;
  // hit (a cell containing p) replaced by the lowest-numbered cell containing p, searched across the
  // faces p lies on.
  Hit lowest_containing(const Eigen::Vector3d& p, Hit hit, int& visited) const;
  const Eigen::Matrix3Xd& nodes_;
  Eigen::Matrix4Xi tets_;       // vertex ids
  Eigen::Matrix4Xi neighbour_;  // cell across the face opposite vertex k, -1 on the boundary
  BucketGrid top_;
  std::vector<int> nested_of_;      // per top bucket: index into nested_, -1 if none
  std::vector<BucketGrid> nested_;  // grids inside the crowded top buckets
};

// B from a solution at points, with locate + evaluate.
class FieldEvaluator {
 public:
  explicit FieldEvaluator(FeSolution solution);
  FieldEvaluator(const FieldEvaluator&) = delete;  // the locator refers to sol_
  FieldEvaluator& operator=(const FieldEvaluator&) = delete;
  const FeSolution& solution() const { return sol_; }
  // B (T) at p (mm); nullopt outside the mesh.
  std::optional<Eigen::Vector3d> B_T(const Eigen::Vector3d& p_mm) const;
  // psi (T*mm) at p (mm); nullopt outside the mesh.
  std::optional<double> psi_Tmm(const Eigen::Vector3d& p_mm) const;
  // B at 3xN points; throws InputError naming the first point outside the mesh. Parallel over
  // fixed chunks of kBatchChunk consecutive points; inside a chunk a point's walk starts in the cell
  // of the nearest of the chunk's last kRecent points when that one lies within about one cell size
  // (probe paths: the same probe one step earlier), else cold. Equal to B_T point by point.
  Eigen::Matrix3Xd B_T(const Eigen::Matrix3Xd& p_mm) const;
  static constexpr int kBatchChunk = 256, kRecent = 32;
  // B at every cell centroid (3 x n_cells).
  Eigen::Matrix3Xd B_cell_centroids() const;

 private:
  FeSolution sol_;
  PointLocator locator_;
};

}  // namespace magenc::fem
