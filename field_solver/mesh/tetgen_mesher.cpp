// TetGen adapter: PLC in, plain TetMesh out. The only file that includes tetgen.h.
#define TETLIBRARY
#include <tetgen.h>

#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "field_solver/mesh/tetgen_mesher.hpp"

namespace magenc::fem {
namespace {

std::string tetgen_reason(int code) {
  switch (code) {
    case 1: return "out of memory";
    case 2: return "internal error";
    case 3: return "self-intersecting input facets (regions overlap or touch)";
    case 4: return "input feature smaller than TetGen's tolerance";
    case 5: return "two input facets too close to each other";
    case 10: return "invalid input";
    default: return "error code " + std::to_string(code);
  }
}

// TetGen in this process: nodes, tets and regions (before finalize_mesh).
TetMesh run_tetgen(const Plc& plc, const MesherOptions& options) {
  tetgenio in, out;
  // 1. Points.
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(plc.points.size());
  in.pointlist = new REAL[3 * in.numberofpoints];
  for (int i = 0; i < in.numberofpoints; ++i)
    for (int d = 0; d < 3; ++d) in.pointlist[3 * i + d] = plc.points[i][d];
  // 2. Facets: the boundary polygon, then any constraint segments / vertices in its plane.
  in.numberoffacets = static_cast<int>(plc.facets.size());
  in.facetlist = new tetgenio::facet[in.numberoffacets];
  in.facetmarkerlist = new int[in.numberoffacets];
  for (int f = 0; f < in.numberoffacets; ++f) {
    tetgenio::facet& tf = in.facetlist[f];
    tetgenio::init(&tf);
    const auto& facet = plc.facets[f];
    tf.numberofpolygons = 1 + static_cast<int>(facet.constraints.size());
    tf.polygonlist = new tetgenio::polygon[tf.numberofpolygons];
    for (int p = 0; p < tf.numberofpolygons; ++p) {
      const auto& poly = p == 0 ? facet.polygon : facet.constraints[static_cast<size_t>(p - 1)];
      tetgenio::polygon& tp = tf.polygonlist[p];
      tetgenio::init(&tp);
      tp.numberofvertices = static_cast<int>(poly.size());
      tp.vertexlist = new int[poly.size()];
      for (size_t k = 0; k < poly.size(); ++k) tp.vertexlist[k] = poly[k];
    }
    in.facetmarkerlist[f] = 1;
  }
  // 3. Regions: seed, attribute (region id), max volume.
  in.numberofregions = static_cast<int>(plc.regions.size());
  in.regionlist = new REAL[5 * in.numberofregions];
  for (int r = 0; r < in.numberofregions; ++r) {
    const auto& reg = plc.regions[r];
    for (int d = 0; d < 3; ++d) in.regionlist[5 * r + d] = reg.seed_mm[d];
    in.regionlist[5 * r + 3] = reg.id;
    in.regionlist[5 * r + 4] = reg.max_volume_mm3 > 0 ? reg.max_volume_mm3 : -1.0;
  }
  // 4. Tetrahedralize: p (PLC), q (quality), A (region attributes), a (region volumes).
  std::ostringstream sw;
  sw << "pq" << options.radius_edge_ratio << "/" << options.min_dihedral_deg << "Aa"
     << (options.verbose ? "V" : "Q");
  if (options.max_added_points > 0) sw << "S" << options.max_added_points;
  std::string switches = sw.str();
  try {
    std::fflush(stdout);
    tetrahedralize(switches.data(), &in, &out);
  } catch (int code) {
    throw ComputeError("TetGen failed: " + tetgen_reason(code));
  }
  if (options.max_added_points > 0 && long(out.numberofpoints) - long(in.numberofpoints) >= options.max_added_points)
    throw InputError("the mesher reached its budget of " + std::to_string(options.max_added_points) +
                     " added points (4 per 5 tetrahedra of the mesh sizes' estimate): allowed geometry the mesh "
                     "sizes resolve (a wall or gap of [[parts]] far below mesh.h_* makes the mesh grow without end)");
  if (out.numberoftetrahedra <= 0 || out.numberoftetrahedronattributes < 1)
    throw ComputeError("TetGen failed: no tetrahedra with region attributes produced");
  // 5. Copy out into the plain mesh struct.
  TetMesh mesh;
  mesh.nodes.resize(3, out.numberofpoints);
  for (int i = 0; i < out.numberofpoints; ++i)
    for (int d = 0; d < 3; ++d) mesh.nodes(d, i) = out.pointlist[3 * i + d];
  mesh.tets.resize(4, out.numberoftetrahedra);
  mesh.region.resize(out.numberoftetrahedra);
  const int nc = out.numberofcorners;  // 4 (linear)
  const int na = out.numberoftetrahedronattributes;
  for (int t = 0; t < out.numberoftetrahedra; ++t) {
    for (int k = 0; k < 4; ++k) mesh.tets(k, t) = out.tetrahedronlist[nc * t + k] - out.firstnumber;
    mesh.region[t] = static_cast<int>(out.tetrahedronattributelist[na * t] + 0.5);
  }
  return mesh;
}

// The child's answer on the pipe: a kind byte (0 mesh, 1 InputError, 2 ComputeError, 3 other), then for a
// mesh the node and tet counts and the arrays, for an error its message.
void write_all(int fd, const void* data, std::size_t n) {
  const char* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) ::_exit(4);
    p += w;
    n -= std::size_t(w);
  }
}

[[noreturn]] void child_mesh(int fd, pid_t parent, const Plc& plc, const MesherOptions& options) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // a killed parent takes the mesher with it
  if (::getppid() != parent) ::_exit(5);  // it died before the line above
  char kind = 0;
  std::string message;
  try {
    const TetMesh m = run_tetgen(plc, options);
    const long counts[2] = {long(m.nodes.cols()), long(m.tets.cols())};
    write_all(fd, &kind, 1);
    write_all(fd, counts, sizeof counts);
    write_all(fd, m.nodes.data(), sizeof(double) * std::size_t(m.nodes.size()));
    write_all(fd, m.tets.data(), sizeof(int) * std::size_t(m.tets.size()));
    write_all(fd, m.region.data(), sizeof(int) * std::size_t(m.region.size()));
    ::_exit(0);
  } catch (const InputError& e) {
    kind = 1, message = e.what();
  } catch (const ComputeError& e) {
    kind = 2, message = e.what();
  } catch (const std::exception& e) {
    kind = 3, message = e.what();
  } catch (...) {
    kind = 3, message = "TetGen failed: an unknown exception";
  }
  write_all(fd, &kind, 1);
  write_all(fd, message.data(), message.size());
  ::_exit(0);
}

// Reads everything the child writes until it closes the pipe or the deadline passes (false).
bool read_until(int fd, std::chrono::steady_clock::time_point deadline, std::string& buf) {
  char chunk[1 << 16];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    pollfd pfd{fd, POLLIN, 0};
    const int r = ::poll(&pfd, 1, int(std::min<long long>(left.count(), 1000)));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) continue;
    const ssize_t n = ::read(fd, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return true;
    buf.append(chunk, std::size_t(n));
  }
}

// The mesh from the child's bytes (a mesh the child wrote whole), or the child's error rethrown.
TetMesh mesh_from_child(const std::string& buf) {
  if (buf.empty()) throw ComputeError("TetGen failed: the mesher process ended without an answer");
  const char kind = buf[0];
  if (kind == 1) throw InputError(buf.substr(1));
  if (kind != 0) throw ComputeError(buf.substr(1));
  long counts[2];
  if (buf.size() < 1 + sizeof counts) throw ComputeError("TetGen failed: the mesher's answer is cut short");
  std::memcpy(counts, buf.data() + 1, sizeof counts);
  const std::size_t nn = std::size_t(counts[0]), nt = std::size_t(counts[1]);
  const std::size_t need = 1 + sizeof counts + sizeof(double) * 3 * nn + sizeof(int) * 5 * nt;
  if (buf.size() != need) throw ComputeError("TetGen failed: the mesher's answer is cut short");
  TetMesh m;
  m.nodes.resize(3, Eigen::Index(nn));
  m.tets.resize(4, Eigen::Index(nt));
  m.region.resize(Eigen::Index(nt));
  const char* p = buf.data() + 1 + sizeof counts;
  std::memcpy(m.nodes.data(), p, sizeof(double) * 3 * nn);
  p += sizeof(double) * 3 * nn;
  std::memcpy(m.tets.data(), p, sizeof(int) * 4 * nt);
  p += sizeof(int) * 4 * nt;
  std::memcpy(m.region.data(), p, sizeof(int) * nt);
  return m;
}

// TetGen in a child process, stopped (and refused) past options.max_seconds; a crash inside TetGen is a
// computation error of this process, not its end.
TetMesh run_tetgen_bounded(const Plc& plc, const MesherOptions& options) {
  int fds[2];
  if (::pipe(fds) != 0) throw ComputeError(std::string("TetGen: cannot create a pipe: ") + std::strerror(errno));
  std::fflush(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]), ::close(fds[1]);
    throw ComputeError(std::string("TetGen: cannot start the mesher process: ") + std::strerror(errno));
  }
  if (pid == 0) {
    ::close(fds[0]);
    child_mesh(fds[1], parent, plc, options);
  }
  ::close(fds[1]);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                              std::chrono::duration<double>(options.max_seconds));
  std::string buf;
  const bool done = read_until(fds[0], deadline, buf);
  ::close(fds[0]);
  if (!done) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!done) {
    std::ostringstream os;
    os << "the mesher ran past its time budget of " << options.max_seconds
       << " s (mesh.max_mesher_seconds): allowed geometry the mesh sizes resolve, or a larger budget for a mesh this fine";
    throw InputError(os.str());
  }
  if (WIFSIGNALED(status))
    throw ComputeError("TetGen failed: the mesher process ended on signal " + std::to_string(WTERMSIG(status)) +
                       " (" + strsignal(WTERMSIG(status)) + ")");
  return mesh_from_child(buf);
}

}  // namespace

TetMesh tetrahedralize_plc(const Plc& plc, const MesherOptions& options) {
  if (plc.points.empty() || plc.facets.empty())
    throw ComputeError("TetGen: empty geometry (no facets)");
  TetMesh mesh = options.max_seconds > 0 ? run_tetgen_bounded(plc, options) : run_tetgen(plc, options);
  finalize_mesh(mesh);
  return mesh;
}

}  // namespace magenc::fem
