// Lagrange P1/P2 tetrahedron: barycentric geometry, basis values and
// gradients, quadrature rules. Local node order is VTK's (VTK_TETRA,
// VTK_QUADRATIC_TETRA): vertices 0..3, then edge midpoints 01 12 20 03 13 23.
#pragma once
#include <Eigen/Dense>
#include <array>

namespace magenc::fem {

inline constexpr int kTetEdges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
inline constexpr int dofs_per_cell(int order) { return order == 1 ? 4 : 10; }

// Affine tet: gradients of the barycentric coordinates (1/mm) and volume (mm^3).
struct TetGeometry {
  Eigen::Matrix<double, 3, 4> grad_L;  // column k = grad L_k (1/mm)
  double volume_mm3 = 0;               // signed volume (> 0 for positive orientation)
  Eigen::Vector3d x0;                  // vertex 0 (mm)
  Eigen::Matrix3d Jinv;                // inverse of [x1-x0, x2-x0, x3-x0]
};

template <class Nodes, class Ids>
TetGeometry tet_geometry(const Nodes& nodes, const Ids& v) {
  TetGeometry g;
  g.x0 = nodes.col(v[0]);
  Eigen::Matrix3d J;
  for (int k = 0; k < 3; ++k) J.col(k) = nodes.col(v[k + 1]) - g.x0;
  g.volume_mm3 = J.determinant() / 6.0;
  g.Jinv = J.inverse();
  // L_{k+1} = row k of Jinv applied to (x - x0); L_0 = 1 - sum.
  for (int k = 0; k < 3; ++k) g.grad_L.col(k + 1) = g.Jinv.row(k).transpose();
  g.grad_L.col(0) = -(g.grad_L.col(1) + g.grad_L.col(2) + g.grad_L.col(3));
  return g;
}

// Barycentric coordinates of p (mm) in the tet.
inline Eigen::Vector4d barycentric(const TetGeometry& g, const Eigen::Vector3d& p) {
  Eigen::Vector3d l = g.Jinv * (p - g.x0);
  return {1.0 - l.sum(), l[0], l[1], l[2]};
}

// Barycentric coordinates of p (mm) in the tet with vertex ids v, without the rest of TetGeometry:
// the same arithmetic as barycentric(tet_geometry(nodes, v), p), so the same bits.
template <class Nodes, class Ids>
Eigen::Vector4d barycentric(const Nodes& nodes, const Ids& v, const Eigen::Vector3d& p) {
  const Eigen::Vector3d x0 = nodes.col(v[0]);
  Eigen::Matrix3d J;
  for (int k = 0; k < 3; ++k) J.col(k) = nodes.col(v[k + 1]) - x0;
  const Eigen::Matrix3d Jinv = J.inverse();
  const Eigen::Vector3d l = Jinv * (p - x0);
  return {1.0 - l.sum(), l[0], l[1], l[2]};
}

// P1/P2 Lagrange basis of a simplex with V vertices at barycentric point L: N[0..V) the vertex
// functions, then (order 2) N[V + e] = 4 L_a L_b of each edge e = (a, b) of `edges`.
template <int V, int E, class Bary>
inline void simplex_basis_values(int order, const Bary& L, const int (&edges)[E][2], double* N) {
  if (order == 1) {
    for (int i = 0; i < V; ++i) N[i] = L[i];
    return;
  }
  for (int i = 0; i < V; ++i) N[i] = L[i] * (2.0 * L[i] - 1.0);
  for (int e = 0; e < E; ++e) N[V + e] = 4.0 * L[edges[e][0]] * L[edges[e][1]];
}

// Basis values at barycentric point L: N (dofs_per_cell).
inline void basis_values(int order, const Eigen::Vector4d& L, double* N) {
  simplex_basis_values<4, 6>(order, L, kTetEdges, N);
}

// Basis gradients (1/mm) at barycentric point L: G is 3 x dofs_per_cell.
inline void basis_gradients(int order, const TetGeometry& g, const Eigen::Vector4d& L,
                            Eigen::Matrix<double, 3, 10>& G) {
  if (order == 1) {
    G.leftCols<4>() = g.grad_L;
    return;
  }
  for (int i = 0; i < 4; ++i) G.col(i) = (4.0 * L[i] - 1.0) * g.grad_L.col(i);
  for (int e = 0; e < 6; ++e) {
    const int a = kTetEdges[e][0], b = kTetEdges[e][1];
    G.col(4 + e) = 4.0 * (L[b] * g.grad_L.col(a) + L[a] * g.grad_L.col(b));
  }
}

// 4-point tet rule, exact for degree 2 (weights sum to 1, multiply by volume).
inline const std::array<Eigen::Vector4d, 4>& tet_quadrature_points() {
  static const std::array<Eigen::Vector4d, 4> q = [] {
    const double a = 0.5854101966249685, b = 0.1381966011250105;
    return std::array<Eigen::Vector4d, 4>{Eigen::Vector4d(a, b, b, b), Eigen::Vector4d(b, a, b, b),
                                          Eigen::Vector4d(b, b, a, b), Eigen::Vector4d(b, b, b, a)};
  }();
  return q;
}
inline constexpr double kTetQuadratureWeight = 0.25;

// 6-point triangle rule, exact for degree 4 (barycentric points, weights sum to 1).
struct TriQuadrature {
  std::array<Eigen::Vector3d, 6> points;
  std::array<double, 6> weights;
};
inline const TriQuadrature& tri_quadrature() {
  static const TriQuadrature q = [] {
    TriQuadrature r;
    const double a1 = 0.445948490915965, b1 = 1.0 - 2.0 * a1, w1 = 0.223381589678011;
    const double a2 = 0.091576213509771, b2 = 1.0 - 2.0 * a2, w2 = 0.109951743655322;
    r.points = {Eigen::Vector3d(a1, a1, b1), Eigen::Vector3d(a1, b1, a1), Eigen::Vector3d(b1, a1, a1),
                Eigen::Vector3d(a2, a2, b2), Eigen::Vector3d(a2, b2, a2), Eigen::Vector3d(b2, a2, a2)};
    r.weights = {w1, w1, w1, w2, w2, w2};
    return r;
  }();
  return q;
}

// Triangle P1/P2 basis at barycentric point l: vertices 0..2 then edges 01 12 20.
inline constexpr int kTriEdges[3][2] = {{0, 1}, {1, 2}, {2, 0}};
inline void tri_basis_values(int order, const Eigen::Vector3d& l, double* N) {
  simplex_basis_values<3, 3>(order, l, kTriEdges, N);
}

}  // namespace magenc::fem
