#include "lane_contact_solver.hpp"

#include <algorithm>
#include <cstddef>
#include <type_traits>

#define RIGID_BODY_CONTACT_LANES_ISA build_isa  // lane_kernel.hpp: the build's own instruction set
#ifdef __AVX__  // a build for this CPU (RIGID_BODY_SIM_NATIVE)
#define RIGID_BODY_CONTACT_LANES_AVX 1
#endif
#include "lane_kernel.hpp"
#undef RIGID_BODY_CONTACT_LANES_AVX
#undef RIGID_BODY_CONTACT_LANES_ISA

namespace rigid_body {
namespace contact {

using namespace build_isa;

namespace {

// The fields of a point slot that are not its directions or Jacobian products (loadFullSlot's lane-by-lane
// part; loadPoint's last lines).
template <class T>
void loadScalars(PointLanes<T>& s, std::size_t l, const SolverContact& c) {
  setLane(s.normal_mass, l, c.normal_mass);
  setLane(s.tangent_mass00, l, c.tangent_mass(0, 0)), setLane(s.tangent_mass01, l, c.tangent_mass(0, 1));
  setLane(s.tangent_mass11, l, c.tangent_mass(1, 1));
  setLane(s.tangent_response00, l, c.tangent_response(0, 0)), setLane(s.tangent_response11, l, c.tangent_response(1, 1));
  setLane(s.tangent_response01, l, 0.5 * (c.tangent_response(0, 1) + c.tangent_response(1, 0)));
  setLane(s.friction, l, c.friction), setLane(s.target_speed, l, c.target_speed);
  setLane(s.normal_floor, l, c.normal_floor), setLane(s.present, l, 1.0);
  setLane(s.normal_impulse, l, c.normal_impulse);
  setLane(s.friction1, l, c.friction_impulse.x()), setLane(s.friction2, l, c.friction_impulse.y());
  setLane(s.slip_squared, l, c.slip_squared);
}

#ifdef RIGID_BODY_WIDE_CONTACT_LANES
bool cpuHasAvx512() {
  static const bool has = __builtin_cpu_supports("avx512f");
  return has;
}
bool cpuHasAvx() {
  static const bool has = __builtin_cpu_supports("avx");
  return has;
}
#endif

// The sweeps of one lane width, in the widest instructions allowed and available.
template <class T>
void runSweepsWidest(bool wide, std::vector<ManifoldLanes<T>>& groups, LaneBodyVelocity* bodies,
                     const SolverContact* contacts, IslandSweeps& islands, char* converged, int iterations) {
#ifdef RIGID_BODY_WIDE_CONTACT_LANES
  if constexpr (std::is_same_v<T, EightLanes>) {
    if (wide && cpuHasAvx512()) return runSweepsAvx512(groups, bodies, contacts, islands, converged, iterations);
  }
  if constexpr (!std::is_same_v<T, double>) {
    if (wide && cpuHasAvx()) return runSweepsAvx(groups, bodies, contacts, islands, converged, iterations);
  }
#endif
  (void)wide;
  runSweeps(groups, bodies, contacts, islands, converged, iterations);
}

}  // namespace

template <class T>
void loadPoint(PointLanes<T>& s, std::size_t l, const SolverContact& c) {
  setLane(s.n, l, c.n), setLane(s.t1, l, c.t1), setLane(s.t2, l, c.t2);
  for (int j = 0; j < 3; ++j) {
    setLane(s.cross_a[j], l, Eigen::Vector3d(c.cross_a.col(j))), setLane(s.cross_b[j], l, Eigen::Vector3d(c.cross_b.col(j)));
    setLane(s.response_a[j], l, Eigen::Vector3d(c.response_a.col(j)));
    setLane(s.response_b[j], l, Eigen::Vector3d(c.response_b.col(j)));
  }
  loadScalars(s, l, c);
}
template void loadPoint(PointLanes<double>&, std::size_t, const SolverContact&);
template void loadPoint(PointLanes<Lanes>&, std::size_t, const SolverContact&);
template void loadPoint(PointLanes<EightLanes>&, std::size_t, const SolverContact&);

template <class T>
bool slotLoadsTransposed() {
#ifdef RIGID_BODY_WIDE_CONTACT_LANES
  static const bool transposed = [] {
    const SolverContact c;
    const bool directions = c.t1.data() == c.n.data() + 3 && c.t2.data() == c.n.data() + 6;
    const bool products = c.cross_b.data() == c.cross_a.data() + 9 && c.response_a.data() == c.cross_a.data() + 18 &&
                          c.response_b.data() == c.cross_a.data() + 27;
    using Slot = PointLanes<T>;
    constexpr std::size_t kVec = sizeof(Vec<T>);
    const bool slot = kVec == 3 * sizeof(T) && offsetof(Slot, t1) == offsetof(Slot, n) + kVec &&
                      offsetof(Slot, t2) == offsetof(Slot, n) + 2 * kVec &&
                      offsetof(Slot, cross_b) == offsetof(Slot, cross_a) + 3 * kVec &&
                      offsetof(Slot, response_a) == offsetof(Slot, cross_a) + 6 * kVec &&
                      offsetof(Slot, response_b) == offsetof(Slot, cross_a) + 9 * kVec;
    const bool cpu = std::is_same_v<T, EightLanes> ? cpuHasAvx512() : std::is_same_v<T, Lanes> && cpuHasAvx();
    return cpu && directions && products && slot;
  }();
  return transposed;
#else
  return false;
#endif
}
template bool slotLoadsTransposed<Lanes>();
template bool slotLoadsTransposed<EightLanes>();

template <class T>
void loadFullSlot(PointLanes<T>& s, const SolverContact* const* contacts) {
  constexpr std::size_t kWidth = kLaneCount<T>;
#ifdef RIGID_BODY_WIDE_CONTACT_LANES
  const double* directions[kWidth];
  const double* products[kWidth];
  for (std::size_t l = 0; l < kWidth; ++l) {
    directions[l] = contacts[l]->n.data(), products[l] = contacts[l]->cross_a.data();
  }
  transposeIntoLanes(&s.n.x, directions, 9);             // n, t1, t2
  transposeIntoLanes(&s.cross_a[0].x, products, 36);     // cross_a, cross_b, response_a, response_b
  for (std::size_t l = 0; l < kWidth; ++l) loadScalars(s, l, *contacts[l]);
#else
  for (std::size_t l = 0; l < kWidth; ++l) loadPoint(s, l, *contacts[l]);
#endif
}
template void loadFullSlot(PointLanes<Lanes>&, const SolverContact* const*);
template void loadFullSlot(PointLanes<EightLanes>&, const SolverContact* const*);

std::size_t bestLaneCount(bool wide_instructions) {
#ifdef RIGID_BODY_WIDE_CONTACT_LANES
  if (wide_instructions && cpuHasAvx512()) return 8;
  if (wide_instructions && cpuHasAvx()) return 4;
  return 1;
#elif defined(__AVX512F__)
  return (void)wide_instructions, 8;  // the whole build targets this CPU (RIGID_BODY_SIM_NATIVE)
#elif defined(__AVX__)
  return (void)wide_instructions, 4;
#else
  return (void)wide_instructions, 1;
#endif
}

struct LaneContactSolver::Buffers {
  std::vector<ManifoldLanes<double>> one;
  std::vector<ManifoldLanes<Lanes>> four;
  std::vector<ManifoldLanes<EightLanes>> eight;
  std::vector<LaneBodyVelocity> bodies;  // 0: the environment (a copy, at rest); then the block's bodies
  std::vector<std::size_t> order;        // packGroups' scratch
  IslandSweeps islands;
};

LaneContactSolver::LaneContactSolver() : buffers_(new Buffers) {}
LaneContactSolver::~LaneContactSolver() = default;
LaneContactSolver::LaneContactSolver(LaneContactSolver&&) noexcept = default;
LaneContactSolver& LaneContactSolver::operator=(LaneContactSolver&&) noexcept = default;

namespace {

// A reused group made ready for its manifolds: its face's K⁺ not yet looked for, and the point slots below
// g.slots that not every lane fills (slots [fewest, g.slots)) zero in every lane, as an empty lane reads
// (PointLanes::present); the loads then write every field of the lanes they fill. Slots from g.slots on
// are never read.
template <class T>
void clearUnfilled(ManifoldLanes<T>& g, std::size_t fewest) {
  for (std::size_t p = fewest; p < g.slots; ++p) g.point[p] = PointLanes<T>{};
  for (std::size_t e = 0; e < kJointEntries; ++e) g.inverse[e] = T{};
  g.inverted = T{}, g.joint = T{};
}

// The colouring's manifolds in groups of kLaneCount<T>, colour by colour; an overflow manifold alone. Within
// a colour no two manifolds share a body (but the environment's, never written back), so their order there
// changes no result: taken most points first, a group's lanes hold manifolds of one size, and its slots are
// not spent on lanes with no point in them (a sphere's one point beside a face's four). `order` is scratch.
template <class T>
void packGroups(const ManifoldColouring& colouring, const std::vector<SolverContact>& contacts,
                std::size_t body_base, std::vector<std::size_t>& order, std::vector<ManifoldLanes<T>>& groups,
                bool transposed) {
  constexpr std::size_t kWidth = kLaneCount<T>;
  const auto local = [&](std::size_t s) { return static_cast<std::uint32_t>(s == kEnvironment ? 0 : s - body_base + 1); };
  const std::vector<Manifold>& manifolds = colouring.manifolds();
  // The groups filled so far. The vector's groups up to its size are reused as they stand (clearUnfilled);
  // it is cut to the groups filled at the end, so a later solve with more groups makes those afresh.
  std::size_t used = 0;
  for (std::size_t colour = 0; colour <= ManifoldColouring::kColours; ++colour) {
    const std::size_t width = colour == ManifoldColouring::kColours ? 1 : kWidth;
    const std::size_t start = colouring.colourStart(colour), end = colouring.colourStart(colour + 1);
    order.clear();
    for (std::size_t count = kMaxManifoldPoints; count >= 1; --count) {
      for (std::size_t m = start; m < end; ++m) {
        if (manifolds[m].count == count) order.push_back(m);  // 1 to kMaxManifoldPoints (manifoldLength)
      }
    }
    for (std::size_t i = 0; i < order.size(); i += width) {
      if (used == groups.size()) groups.emplace_back();
      ManifoldLanes<T>& g = groups[used++];
      g.lanes = static_cast<std::uint32_t>(std::min(width, order.size() - i));
      // Most points first: the group's first lane has the most, its last the fewest.
      g.slots = static_cast<std::uint32_t>(manifolds[order[i]].count);
      const std::size_t fewest = g.lanes == kWidth ? manifolds[order[i + g.lanes - 1]].count : 0;
      clearUnfilled(g, fewest);
      for (std::size_t l = 0; l < g.lanes; ++l) {
        const Manifold& manifold = manifolds[order[i + l]];
        const SolverContact& first = contacts[manifold.first];
        g.body_a[l] = local(first.a), g.body_b[l] = local(first.b);
        g.island[l] = manifold.island;
        g.first_contact[l] = manifold.first;
        g.count[l] = static_cast<std::uint32_t>(manifold.count);
      }
      // The slots every lane fills, eight lanes wide, by transposes where they may be; the rest lane by lane.
      std::size_t p = 0;
      if constexpr (!std::is_same_v<T, double>) {
        for (; transposed && p < fewest; ++p) {
          const SolverContact* lanes[kWidth];
          for (std::size_t l = 0; l < kWidth; ++l) lanes[l] = &contacts[g.first_contact[l] + p];
          loadFullSlot(g.point[p], lanes);
        }
      }
      for (; p < g.slots; ++p) {
        for (std::size_t l = 0; l < g.lanes; ++l) {
          if (p < g.count[l]) loadPoint(g.point[p], l, contacts[g.first_contact[l] + p]);
        }
      }
    }
  }
  groups.resize(used);
}

// Whether these groups' full slots are loaded by transposes (one lane never is).
template <class T>
bool fullSlotsTransposed(const std::vector<ManifoldLanes<T>>&) {
  if constexpr (std::is_same_v<T, double>) {
    return false;
  } else {
    return slotLoadsTransposed<T>();
  }
}

// The impulses back into the contacts.
template <class T>
void unpackGroups(const std::vector<ManifoldLanes<T>>& groups, std::vector<SolverContact>& contacts) {
  for (const ManifoldLanes<T>& g : groups) {
    for (std::size_t l = 0; l < g.lanes; ++l) {
      for (std::size_t p = 0; p < g.slots; ++p) {
        const PointLanes<T>& s = g.point[p];
        if (!(laneValue(s.present, l) > 0.0)) break;
        SolverContact& c = contacts[g.first_contact[l] + p];
        c.normal_impulse = laneValue(s.normal_impulse, l);
        c.friction_impulse = Eigen::Vector2d(laneValue(s.friction1, l), laneValue(s.friction2, l));
        c.slip_squared = laneValue(s.slip_squared, l);
      }
    }
  }
}

}  // namespace

namespace {

// Each island's solve copies its bodies' velocities into the block's store (0: the environment, at rest),
// and back. Only the islands' own bodies are read and written: other blocks' may lie between them, on
// other threads.
void gatherBodies(const std::vector<SolverBody>& bodies, const SolveRange* islands, std::size_t count,
                  std::size_t base, std::vector<LaneBodyVelocity>& store) {
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t s = std::max<std::size_t>(islands[i].body_begin, 1); s < islands[i].body_end; ++s) {
      LaneBodyVelocity& to = store[s - base + 1];
      for (int j = 0; j < 3; ++j) to.v[j] = bodies[s].v[j], to.w[j] = bodies[s].w[j];
      to.inverse_mass = bodies[s].inverse_mass;
    }
  }
}
void scatterBodies(const std::vector<LaneBodyVelocity>& store, const SolveRange* islands, std::size_t count,
                   std::size_t base, std::vector<SolverBody>& bodies) {
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t s = std::max<std::size_t>(islands[i].body_begin, 1); s < islands[i].body_end; ++s) {
      const LaneBodyVelocity& from = store[s - base + 1];
      bodies[s].v = Eigen::Vector3d(from.v[0], from.v[1], from.v[2]);
      bodies[s].w = Eigen::Vector3d(from.w[0], from.w[1], from.w[2]);
    }
  }
}

}  // namespace

void LaneContactSolver::solve(std::vector<SolverContact>& contacts, std::vector<SolverBody>& bodies,
                              const SolveOptions& options, const SolveRange* islands, std::size_t count,
                              char* converged, const LaneSettings& lanes) {
  Buffers& buffers = *buffers_;
  colouring_.colour(contacts, islands, count, bodies.size());
  IslandSweeps& sweeps = buffers.islands;
  sweeps.allowed.resize(count), sweeps.live.resize(count), sweeps.change.resize(count), sweeps.impulse.resize(count);
  std::size_t body_base = bodies.size(), body_end = 0;
  for (std::size_t i = 0; i < count; ++i) {
    body_base = std::min(body_base, std::max<std::size_t>(islands[i].body_begin, 1));
    body_end = std::max(body_end, islands[i].body_end);
    sweeps.allowed[i] = allowedSweeps(options, islands[i].contact_end - islands[i].contact_begin);
    converged[i] = 0;
  }
  body_end = std::max(body_end, body_base);
  buffers.bodies.assign(body_end - body_base + 1, LaneBodyVelocity{{0, 0, 0}, {0, 0, 0}, 0.0, 0.0});
  gatherBodies(bodies, islands, count, body_base, buffers.bodies);
  const auto sweep = [&](auto& groups) {
    const bool transposed = lanes.wide_instructions && fullSlotsTransposed(groups);
    packGroups(colouring_, contacts, body_base, buffers.order, groups, transposed);
    runSweepsWidest(lanes.wide_instructions, groups, buffers.bodies.data(), contacts.data(), sweeps, converged,
                    options.iterations);
    unpackGroups(groups, contacts);
  };
  const std::size_t width = lanes.lanes == 0 ? bestLaneCount(lanes.wide_instructions) : lanes.lanes;
  if (width == 1) {
    sweep(buffers.one);
  } else if (width == 4) {
    sweep(buffers.four);
  } else {
    sweep(buffers.eight);
  }
  scatterBodies(buffers.bodies, islands, count, body_base, bodies);
}

std::vector<std::size_t> LaneContactSolver::sweepOrder() const {
  std::vector<std::size_t> order;
  for (const Manifold& m : colouring_.manifolds()) {
    for (std::size_t p = 0; p < m.count; ++p) order.push_back(m.first + p);
  }
  return order;
}

}  // namespace contact
}  // namespace rigid_body
