#include "field_solver/fe/assembly.hpp"

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "field_solver/fe/element.hpp"

namespace magenc::fem {

namespace {

// Element stiffness in closed form. With A_pq = V grad L_p . grad L_q (the P1 stiffness,
// 10 distinct values for p <= q), every basis gradient is grad N_i = sum_p c_ip(L) grad L_p
// with c_ip linear in the barycentric coordinates L (P1 vertex: 1; P2 vertex a:
// (4 L_a - 1) at p = a; P2 edge (a, b): 4 L_b at p = a, 4 L_a at p = b). So
//   K_ij = sum_{p <= q} A_pq W[i][j][pq],  W = the means over the tet of c_ip c_jq (+ c_iq c_jp),
// exact with the tet's means <1> = 1, <L_k> = 1/4, <L_k L_l> = 1/10 (k = l) or 1/20: the
// same integral the 4-point rule (exact for degree 2) computes, without the quadrature loop.
// W as ND x ND matrices, one per pair (p <= q); both triangles from the one value.
template <int ND> struct FullWeights {
  alignas(64) double w[10][ND * ND];
  FullWeights() {
    // c_ip = alpha[i][p] + sum_k beta[i][p][k] L_k
    double alpha[ND][4] = {}, beta[ND][4][4] = {};
    for (int a = 0; a < 4; ++a) {
      if (ND == 4) {
        alpha[a][a] = 1.0;
      } else {
        alpha[a][a] = -1.0;
        beta[a][a][a] = 4.0;
      }
    }
    if (ND == 10)
      for (int e = 0; e < 6; ++e) {
        const int a = kTetEdges[e][0], b = kTetEdges[e][1];
        beta[4 + e][a][b] = 4.0;
        beta[4 + e][b][a] = 4.0;
      }
    auto mean = [&](int i, int p, int j, int q) {  // <c_ip c_jq>
      double m = alpha[i][p] * alpha[j][q];
      for (int k = 0; k < 4; ++k) m += 0.25 * (alpha[i][p] * beta[j][q][k] + alpha[j][q] * beta[i][p][k]);
      for (int k = 0; k < 4; ++k)
        for (int l = 0; l < 4; ++l) m += beta[i][p][k] * beta[j][q][l] * (k == l ? 0.1 : 0.05);
      return m;
    };
    for (int i = 0; i < ND; ++i)
      for (int j = i; j < ND; ++j) {
        int k = 0;
        for (int p = 0; p < 4; ++p)
          for (int q = p; q < 4; ++q, ++k)
            w[k][i * ND + j] = w[k][j * ND + i] = p == q ? mean(i, p, j, p) : mean(i, p, j, q) + mean(i, q, j, p);
      }
  }
};
template <int ND> const FullWeights<ND> kWeights;

// Ke (row-major ND x ND) of cell t with mu_r: sum_k A_k W_k, the same operations for
// (i, j) and (j, i), so Ke is exactly symmetric.
template <int ND> inline void element_stiffness(const TetMesh& mesh, int t, double mu_r, double* Ke) {
  const FullWeights<ND>& W = kWeights<ND>;
  const TetGeometry g = tet_geometry(mesh.nodes, mesh.tets.col(t));
  double A[10];
  const double s = mu_r * g.volume_mm3;
  for (int p = 0, k = 0; p < 4; ++p)
    for (int q = p; q < 4; ++q, ++k) A[k] = s * g.grad_L.col(p).dot(g.grad_L.col(q));
  for (int e = 0; e < ND * ND; ++e) Ke[e] = A[0] * W.w[0][e];
  for (int k = 1; k < 10; ++k)
    for (int e = 0; e < ND * ND; ++e) Ke[e] += A[k] * W.w[k][e];
}

}  // namespace

void cell_stiffness(const TetMesh& mesh, int order, int t, double mu_r, Eigen::Matrix<double, 10, 10>& Ke) {
  double k[100];
  const int nd = order == 1 ? 4 : 10;
  if (order == 1)
    element_stiffness<4>(mesh, t, mu_r, k);
  else
    element_stiffness<10>(mesh, t, mu_r, k);
  Ke.setZero();
  for (int i = 0; i < nd; ++i)
    for (int j = 0; j < nd; ++j) Ke(i, j) = k[i * nd + j];
}

int robin_face_matrix(const TetMesh& mesh, const FeSpace& space, Eigen::Index f, int dofs[6],
                      Eigen::Matrix<double, 6, 6>& Me) {
  const int order = space.order();
  const auto& q = tri_quadrature();
  const int nf = order == 1 ? 3 : 6;
  int v[3];
  for (int k = 0; k < 3; ++k) dofs[k] = v[k] = mesh.boundary_faces(k, f);
  if (order == 2)
    for (int e = 0; e < 3; ++e) dofs[3 + e] = space.edge_dof(v[kTriEdges[e][0]], v[kTriEdges[e][1]]);
  const Eigen::Vector3d x0 = mesh.nodes.col(v[0]), x1 = mesh.nodes.col(v[1]), x2 = mesh.nodes.col(v[2]);
  const double area = 0.5 * (x1 - x0).cross(x2 - x0).norm();
  Me.setZero();
  double N[6];
  for (int k = 0; k < 6; ++k) {
    const Eigen::Vector3d& l = q.points[k];
    const double r = (l[0] * x0 + l[1] * x1 + l[2] * x2).norm();
    tri_basis_values(order, l, N);
    const double w = q.weights[k] * area * 2.0 / r;
    for (int i = 0; i < nf; ++i)
      for (int j = 0; j < nf; ++j) Me(i, j) += w * N[i] * N[j];
  }
  return nf;
}

namespace {

// Position of column c in CSR row r (columns sorted); -1 if absent.
inline long long find_entry(const int* outer, const int* inner, int r, int c) {
  const int* b = inner + outer[r];
  const int* e = inner + outer[r + 1];
  const int* it = std::lower_bound(b, e, c);
  return it != e && *it == c ? static_cast<long long>(it - inner) : -1;
}

template <int ND>
void assemble_cells(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r_cell, int threads,
                    int chunk_cells, SparseMatrix& K) {
  const int nt = mesh.num_tets();
  const int n = space.num_dofs();
  const Eigen::MatrixXi& cd = space.cell_dofs();

  // 1. dof -> (cell, local index) adjacency by counting sort, cells ascending per dof.
  //    Entry value t * ND + i (int: nt * ND is checked).
  if (static_cast<long long>(nt) * ND > std::numeric_limits<int>::max())
    throw std::runtime_error("assemble_stiffness: mesh too large for 32-bit element-entry indices");
  std::vector<long long> adj_ptr(static_cast<size_t>(n) + 1, 0);
  for (int t = 0; t < nt; ++t)
    for (int i = 0; i < ND; ++i) ++adj_ptr[static_cast<size_t>(cd(i, t)) + 1];
  for (int d = 0; d < n; ++d) adj_ptr[d + 1] += adj_ptr[d];
  std::vector<int> adj(static_cast<size_t>(adj_ptr[n]));
  {
    std::vector<long long> fill(adj_ptr.begin(), adj_ptr.end() - 1);
    for (int t = 0; t < nt; ++t)
      for (int i = 0; i < ND; ++i) adj[static_cast<size_t>(fill[static_cast<size_t>(cd(i, t))]++)] = t * ND + i;
  }

  // 2. CSR pattern: row r holds the sorted union of the dofs of the cells around r
  //    (the pattern setFromTriplets produced; boundary faces are faces of cells, so
  //    the Robin term adds no entries). Thread k handles the rows [n k / T, n (k+1) / T)
  //    into its own column buffer (row lengths into outer[r + 1]), then the buffers are
  //    concatenated: the result does not depend on the thread count.
  int* outer = K.outerIndexPtr();
  outer[0] = 0;
  std::vector<std::vector<int>> cols(static_cast<size_t>(threads));
  int blocks = 1;
#pragma omp parallel num_threads(threads)
  {
    const int tid = omp_get_thread_num();
    const int nth = omp_get_num_threads();
#pragma omp single
    blocks = nth;
    const int r0 = static_cast<int>(static_cast<long long>(n) * tid / nth);
    const int r1 = static_cast<int>(static_cast<long long>(n) * (tid + 1) / nth);
    std::vector<int>& out = cols[static_cast<size_t>(tid)];
    out.reserve(static_cast<size_t>(adj_ptr[r1] - adj_ptr[r0]) * 4);
    // The row's columns as bits of a bitmap over all dofs (n / 8 bytes: stays in cache), with
    // the list of its words that became non-zero; sorting those few words and reading
    // their bits in order gives the sorted, de-duplicated columns and clears the bitmap.
    std::vector<std::uint64_t> bits((static_cast<size_t>(n) + 63) / 64, 0);
    std::vector<int> words(static_cast<size_t>(ND) * 64);
    std::vector<int> row(static_cast<size_t>(ND) * 64);
    for (int r = r0; r < r1; ++r) {
      const size_t cap = static_cast<size_t>(adj_ptr[r + 1] - adj_ptr[r]) * ND;
      if (row.size() < cap) {
        row.resize(cap);
        words.resize(cap);
      }
      int nw = 0;
      for (long long a = adj_ptr[r]; a < adj_ptr[r + 1]; ++a) {
        const int* dofs = &cd(0, adj[static_cast<size_t>(a)] / ND);
        for (int j = 0; j < ND; ++j) {  // branchless
          const int c = dofs[j];
          const size_t w = static_cast<size_t>(c) >> 6;
          const std::uint64_t old = bits[w];
          words[static_cast<size_t>(nw)] = static_cast<int>(w);
          nw += old == 0;
          bits[w] = old | (std::uint64_t{1} << (c & 63));
        }
      }
      std::sort(words.begin(), words.begin() + nw);
      int len = 0;
      for (int k = 0; k < nw; ++k) {
        const size_t w = static_cast<size_t>(words[static_cast<size_t>(k)]);
        std::uint64_t b = bits[w];
        bits[w] = 0;
        for (; b != 0; b &= b - 1) row[static_cast<size_t>(len++)] = static_cast<int>(w * 64) + __builtin_ctzll(b);
      }
      out.insert(out.end(), row.begin(), row.begin() + len);
      outer[r + 1] = len;
    }
  }
  long long nnz = 0;
  for (int r = 0; r < n; ++r) {
    nnz += outer[r + 1];
    if (nnz > std::numeric_limits<int>::max())
      throw std::runtime_error("assemble_stiffness: matrix too large for 32-bit sparse indices");
    outer[r + 1] = static_cast<int>(nnz);
  }
  K.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* inner = K.innerIndexPtr();
  double* val = K.valuePtr();
#pragma omp parallel for num_threads(threads) schedule(static, 1)
  for (int b = 0; b < blocks; ++b) {
    const int r0 = static_cast<int>(static_cast<long long>(n) * b / blocks);
    std::vector<int>& in = cols[static_cast<size_t>(b)];
    std::copy(in.begin(), in.end(), inner + outer[r0]);
    std::vector<int>().swap(in);
    // -0.0 is the exact additive identity (-0.0 + x == x bitwise for every x,
    // +0.0 and -0.0 included): each entry becomes its first contribution, then
    // the later ones are added in order, as setFromTriplets summed duplicates.
    const int r1 = static_cast<int>(static_cast<long long>(n) * (b + 1) / blocks);
    std::fill(val + outer[r0], val + outer[r1], -0.0);
  }

  // 3. Element matrices in chunks of cells, computed in parallel into a buffer, then
  //    scattered row-wise: the rows touched by the chunk are split among the threads
  //    (each row has one owner) and each adds the contributions of the chunk's cells
  //    in ascending cell order (a cursor into the row's adjacency), finding columns
  //    through a dense position map of the row (pos[column] = offset in the row).
  //    Every entry is thus summed in element order, for any thread count.
  const int kChunk = std::max(1, chunk_cells);
  constexpr size_t ke_size = static_cast<size_t>(ND) * ND;
  std::vector<double> buf(static_cast<size_t>(std::min(kChunk, std::max(nt, 1))) * ke_size);
  std::vector<long long> cursor(adj_ptr.begin(), adj_ptr.end() - 1);
  std::vector<int> stamp(static_cast<size_t>(n), -1);
  std::vector<int> touched;  // rows with a cell in the current chunk (any order: rows are independent)
  touched.reserve(static_cast<size_t>(std::min(static_cast<long long>(n), static_cast<long long>(kChunk) * ND)));
#pragma omp parallel num_threads(threads)
  {
    std::vector<int> pos(static_cast<size_t>(n));
    for (int c0 = 0; c0 < nt; c0 += kChunk) {
      const int c1 = std::min(nt, c0 + kChunk);
#pragma omp single nowait
      {
        touched.clear();
        for (int t = c0; t < c1; ++t)
          for (int i = 0; i < ND; ++i) {
            const int r = cd(i, t);
            if (stamp[static_cast<size_t>(r)] != c0) {
              stamp[static_cast<size_t>(r)] = c0;
              touched.push_back(r);
            }
          }
      }
#pragma omp for schedule(static)
      for (int t = c0; t < c1; ++t)
        element_stiffness<ND>(mesh, t, mu_r_cell[t], buf.data() + static_cast<size_t>(t - c0) * ke_size);
      // implicit barrier: the chunk's element matrices and row list are complete
      const int n_touched = static_cast<int>(touched.size());
#pragma omp for schedule(static)
      for (int q = 0; q < n_touched; ++q) {
        const int r = touched[static_cast<size_t>(q)];
        const int b = outer[r], len = outer[r + 1] - b;
        for (int k = 0; k < len; ++k) pos[static_cast<size_t>(inner[b + k])] = k;
        long long a = cursor[static_cast<size_t>(r)];
        const long long a_end = adj_ptr[static_cast<size_t>(r) + 1];
        double* vr = val + b;
        for (; a < a_end; ++a) {
          const int e = adj[static_cast<size_t>(a)];
          const int t = e / ND;
          if (t >= c1) break;
          const int i = e - t * ND;
          const double* row = buf.data() + static_cast<size_t>(t - c0) * ke_size + static_cast<size_t>(i) * ND;
          const int* dofs = &cd(0, t);
          for (int j = 0; j < ND; ++j) vr[pos[static_cast<size_t>(dofs[j])]] += row[j];
        }
        cursor[static_cast<size_t>(r)] = a;
      }  // implicit barrier: the buffer and row list may be overwritten by the next chunk
    }
  }
}

}  // namespace

SparseMatrix assemble_stiffness(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r_cell,
                                bool robin, int threads, int chunk_cells) {
  threads = std::max(1, threads);
  SparseMatrix K(space.num_dofs(), space.num_dofs());
  if (space.order() == 1)
    assemble_cells<4>(mesh, space, mu_r_cell, threads, chunk_cells, K);
  else
    assemble_cells<10>(mesh, space, mu_r_cell, threads, chunk_cells, K);

  // 4. Robin term on the truncation sphere: Int (2/r) N_i N_j dS (mu_r = 1 in air),
  //    added after all cells, in face order.
  if (robin) {
    const int* outer = K.outerIndexPtr();
    const int* inner = K.innerIndexPtr();
    double* val = K.valuePtr();
    int dofs[6];
    Eigen::Matrix<double, 6, 6> Me;
    for (Eigen::Index f = 0; f < mesh.boundary_faces.cols(); ++f) {
      const int nf = robin_face_matrix(mesh, space, f, dofs, Me);
      for (int i = 0; i < nf; ++i)
        for (int j = 0; j < nf; ++j) {
          const long long k = dofs[i] < 0 || dofs[j] < 0 ? -1 : find_entry(outer, inner, dofs[i], dofs[j]);
          if (k < 0)
            throw std::logic_error("assemble_stiffness: boundary face " + std::to_string(f) +
                                   " is not a face of a cell");
          val[k] += Me(i, j);
        }
    }
  }
  return K;
}

Eigen::VectorXd assemble_rhs(const TetMesh& mesh, const FeSpace& space, const Eigen::Matrix3Xd& br_cell) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(space.num_dofs());
  const int order = space.order();
  const int nd = space.dofs_per_cell();
  Eigen::Matrix<double, 3, 10> G;
  // Serial: only magnet cells contribute, and a fixed order keeps f bitwise reproducible.
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Eigen::Vector3d br = br_cell.col(t);
    if (br.squaredNorm() == 0.0) continue;
    const TetGeometry g = tet_geometry(mesh.nodes, mesh.tets.col(t));
    Eigen::Matrix<double, 10, 1> fe = Eigen::Matrix<double, 10, 1>::Zero();
    if (order == 1) {
      basis_gradients(1, g, Eigen::Vector4d::Constant(0.25), G);
      fe.head<4>() = g.volume_mm3 * G.leftCols<4>().transpose() * br;
    } else {
      for (const auto& L : tet_quadrature_points()) {
        basis_gradients(2, g, L, G);
        fe += (kTetQuadratureWeight * g.volume_mm3) * G.transpose() * br;
      }
    }
    for (int i = 0; i < nd; ++i) f[space.cell_dofs()(i, t)] += fe[i];
  }
  return f;
}

std::vector<int> boundary_dofs(const TetMesh& mesh, const FeSpace& space) {
  std::vector<int> d;
  for (Eigen::Index f = 0; f < mesh.boundary_faces.cols(); ++f)
    for (int k = 0; k < 3; ++k) {
      d.push_back(mesh.boundary_faces(k, f));
      if (space.order() == 2)
        d.push_back(space.edge_dof(mesh.boundary_faces(kTriEdges[k][0], f), mesh.boundary_faces(kTriEdges[k][1], f)));
    }
  std::sort(d.begin(), d.end());
  d.erase(std::unique(d.begin(), d.end()), d.end());
  return d;
}

void apply_zero_dirichlet(SparseMatrix& K, Eigen::VectorXd& f, const std::vector<int>& dofs) {
  std::vector<char> fixed(static_cast<size_t>(K.rows()), 0);
  for (int d : dofs) fixed[static_cast<size_t>(d)] = 1;
  for (Eigen::Index r = 0; r < K.outerSize(); ++r)
    for (SparseMatrix::InnerIterator it(K, r); it; ++it)
      if (fixed[static_cast<size_t>(it.row())] || fixed[static_cast<size_t>(it.col())])
        it.valueRef() = it.row() == it.col() ? 1.0 : 0.0;
  for (int d : dofs) f[d] = 0.0;
}

}  // namespace magenc::fem
