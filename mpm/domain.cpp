#include "mpm/domain.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include "common/base/error.hpp"
#include "mpm/kernels.hpp"

namespace slide::mpm {

// ----------------------------------------------------------------------------- cuts

int SlabCuts::owner_of_column(int cell_column) const {
  const auto after = std::upper_bound(begin.begin(), begin.end(), cell_column);
  const auto rank = static_cast<int>(after - begin.begin()) - 1;
  return std::clamp(rank, 0, ranks() - 1);
}

void SlabCuts::check(int columns) const {
  if (begin.size() < 2 || begin.front() != 0 || begin.back() != columns) {
    throw Error("mpm: slab cuts must run from cell column 0 to the grid's {}", columns);
  }
  for (std::size_t r = 0; r + 1 < begin.size(); ++r) {
    if (begin[r + 1] - begin[r] < min_slab_cells) {
      throw Error("mpm: slab {} (cell columns {}–{}) is narrower than {} cells", r, begin[r],
                  begin[r + 1] - 1, min_slab_cells);
    }
  }
}

SlabCuts SlabCuts::balanced(std::span<const std::int64_t> particles_per_column, int ranks) {
  const auto columns = static_cast<int>(particles_per_column.size());
  if (ranks < 1) throw Error("mpm: {} ranks", ranks);
  if (ranks * min_slab_cells > columns) {
    throw Error(
        "mpm: the grid's {} cell columns cannot be cut into {} slabs of at least {} cells "
        "(run on at most {} ranks, or use smaller cells)",
        columns, ranks, min_slab_cells, columns / min_slab_cells);
  }
  std::int64_t total = 0;
  for (auto n : particles_per_column) total += n;
  SlabCuts cuts;
  cuts.begin.assign(static_cast<std::size_t>(ranks) + 1, 0);
  cuts.begin.back() = columns;
  // Cut k where the particles to its left first reach k/N of all (exact integer test).
  std::int64_t below = 0;
  int k = 1;
  for (int c = 0; c < columns && k < ranks; ++c) {
    while (k < ranks && below * ranks >= static_cast<std::int64_t>(k) * total) {
      cuts.begin[static_cast<std::size_t>(k++)] = c;
    }
    below += particles_per_column[static_cast<std::size_t>(c)];
  }
  for (; k < ranks; ++k) cuts.begin[static_cast<std::size_t>(k)] = columns;
  // Every slab at least min_slab_cells wide: push cuts right, then pull them back left
  // from the grid's end (feasible since ranks · min_slab_cells ≤ columns).
  for (std::size_t r = 1; r < cuts.begin.size() - 1; ++r)
    cuts.begin[r] = std::max(cuts.begin[r], cuts.begin[r - 1] + min_slab_cells);
  for (std::size_t r = cuts.begin.size() - 2; r >= 1; --r)
    cuts.begin[r] = std::min(cuts.begin[r], cuts.begin[r + 1] - min_slab_cells);
  return cuts;
}

int cell_column_of(const GridGeometry& grid, const Vec2& x) {
  const double xi = std::floor((x.x() - grid.origin.x()) / grid.cell_size);
  if (!std::isfinite(xi)) return 0;
  return static_cast<int>(std::clamp(xi, 0.0, static_cast<double>(grid.cells_x - 1)));
}

std::vector<std::int64_t> particles_per_column(const Particles& particles, std::size_t count,
                                               const GridGeometry& grid) {
  std::vector<std::int64_t> histogram(static_cast<std::size_t>(grid.cells_x), 0);
  for (std::size_t p = 0; p < count; ++p)
    ++histogram[static_cast<std::size_t>(cell_column_of(grid, particles.coordinates[p]))];
  return histogram;
}

// ----------------------------------------------------------------------------- packing

namespace {

class ByteWriter {
 public:
  explicit ByteWriter(std::vector<std::byte>& bytes) : bytes_(bytes) {}
  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* first = reinterpret_cast<const std::byte*>(&value);
    bytes_.insert(bytes_.end(), first, first + sizeof(T));
  }
  template <int K>
  void put(const Eigen::Matrix<double, K, 1>& v) {
    for (int i = 0; i < K; ++i) put(v[i]);
  }

 private:
  std::vector<std::byte>& bytes_;
};

class ByteReader {
 public:
  explicit ByteReader(std::span<const std::byte> bytes) : bytes_(bytes) {}
  template <class T>
  void get(T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (at_ + sizeof(T) > bytes_.size()) throw Error("mpm: a particle message ends early");
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
  }
  template <int K>
  void get(Eigen::Matrix<double, K, 1>& v) {
    for (int i = 0; i < K; ++i) get(v[i]);
  }

 private:
  std::span<const std::byte> bytes_;
  std::size_t at_ = 0;
};

}  // namespace

// A packed row is every field of particle_fields in its order, each entry as its bytes;
// the unused fields (APIC's affine velocity in a FLIP run) only when the layout carries
// them, the surface stresses `surfaces` to a particle.
namespace {

template <class T>
std::size_t entry_bytes(const std::vector<T>&) {
  return sizeof(T);
}
/// Whether a field travels in `layout`: always, or an unused one the layout carries (APIC's
/// affine velocity, the saturated transfer's fields).
template <class Field>
bool carried(const Field& field, const PackedLayout& layout) {
  if (field.presence == Presence::always) return true;
  return field.name == "affine_velocity_gradient" ? layout.affine : layout.pore_water;
}

template <class Field>
std::size_t packed_bytes(const Field& field, const Particles& none, const PackedLayout& layout) {
  const auto& column = field.of(none);
  if constexpr (std::is_same_v<std::remove_cvref_t<decltype(column)>, SurfaceStresses>) {
    return layout.surfaces * sizeof(Vec4);
  } else {
    return carried(field, layout) ? entry_bytes(column) : 0;
  }
}

/// f(entry) for every entry of particle k in the packed order (`P` const or not).
template <class P, class F>
void for_each_entry(P& p, std::size_t k, const PackedLayout& layout, F&& f) {
  for_each_field(particle_fields, [&](const auto& field) {
    auto& column = field.of(p);
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(column)>, SurfaceStresses>) {
      for (auto& s : column.of(k)) f(s);
    } else if (carried(field, layout)) {
      f(column[k]);
    }
  });
}

}  // namespace

std::size_t PackedLayout::bytes() const {
  std::size_t total = 0;
  const Particles none;
  for_each_field(particle_fields,
                 [&](const auto& field) { total += packed_bytes(field, none, *this); });
  return total;
}

static void require_layout(const Particles& p, const PackedLayout& layout) {
  if (p.surface_stress.per_point != layout.surfaces ||
      (layout.affine && p.affine_velocity.size() != p.count()) ||
      (layout.pore_water && p.liquefied.size() != p.count())) {
    throw Error(
        "mpm: particles with {} surfaces and {} affine velocities for {} do not match the "
        "packed layout ({} surfaces{})",
        p.surface_stress.per_point, p.affine_velocity.size(), p.count(), layout.surfaces,
        layout.affine ? ", affine" : "");
  }
}

void pack_particles(const Particles& p, std::span<const std::size_t> indices,
                    const PackedLayout& layout, std::vector<std::byte>& bytes) {
  require_layout(p, layout);
  bytes.reserve(bytes.size() + indices.size() * layout.bytes());
  ByteWriter out(bytes);
  for (const std::size_t k : indices)
    for_each_entry(p, k, layout, [&](const auto& v) { out.put(v); });
}

std::size_t unpack_particles(std::span<const std::byte> bytes, const PackedLayout& layout,
                             Particles& p) {
  require_layout(p, layout);
  const std::size_t row = layout.bytes();
  if (bytes.size() % row != 0)
    throw Error("mpm: a particle message of {} bytes is not whole rows of {}", bytes.size(), row);
  const std::size_t first = p.count(), added = bytes.size() / row;
  p.resize(first + added);
  // Particles::resize keeps an empty affine field empty (a rank all of whose particles
  // left has none): the layout, not the particles, says whether rows carry one.
  if (layout.affine) p.affine_velocity.resize(first + added, Vec4::Zero());
  if (layout.pore_water) p.use_pore_water_fields();
  ByteReader in(bytes);
  for (std::size_t k = first; k < first + added; ++k)
    for_each_entry(p, k, layout, [&](auto& v) { in.get(v); });
  return added;
}

namespace {

/// Keeps the particles with keep[k] (in order) and drops the others.
void compact(Particles& p, const std::vector<char>& keep) {
  std::size_t to = 0;
  for (std::size_t from = 0; from < p.count(); ++from) {
    if (!keep[from]) continue;
    if (to != from) move_particle(p, to, from);
    ++to;
  }
  p.resize(to);
}

std::vector<std::size_t> range(std::size_t begin, std::size_t end) {
  std::vector<std::size_t> indices(end - begin);
  for (std::size_t k = begin; k < end; ++k) indices[k - begin] = k;
  return indices;
}

/// The particles after an exchange: the active ones kept (keep[k], in order), then the
/// arrivals (buffers in order), then the frozen ones [active, n), which stay last.
/// Returns the new active count.
std::size_t regroup(Particles& p, std::size_t active, std::vector<char> keep,
                    std::span<const std::vector<std::byte>> arrivals, const PackedLayout& layout) {
  std::vector<std::byte> frozen;
  if (active < p.count()) {
    pack_particles(p, range(active, p.count()), layout, frozen);
    std::fill(keep.begin() + static_cast<std::ptrdiff_t>(active), keep.end(), 0);
  }
  compact(p, keep);
  for (const auto& bytes : arrivals) unpack_particles(bytes, layout, p);
  const std::size_t now_active = p.count();
  unpack_particles(frozen, layout, p);
  return now_active;
}

}  // namespace

// ----------------------------------------------------------------------------- subdomain

Subdomain::Subdomain(const Ranks& ranks, SlabCuts cuts) : ranks_(ranks), cuts_(std::move(cuts)) {
  if (cuts_.ranks() != ranks_.size())
    throw Error("mpm: {} slabs for {} ranks", cuts_.ranks(), ranks_.size());
}

std::pair<int, int> Subdomain::own_node_columns(const GridGeometry& grid) const {
  const int rank = ranks_.rank();
  const int begin = rank == 0 ? 0 : first_cell() + 1;
  const int end = rank == ranks_.size() - 1 ? grid.node_columns() : end_cell() + 1;
  return {begin, end};
}

namespace {

struct PlainVec2 {
  double x, y;
};

void add_into(NodeSums& to, const NodeSums& from) {
  to.mass += from.mass;
  to.momentum_x += from.momentum_x;
  to.momentum_y += from.momentum_y;
  to.force_x += from.force_x;
  to.force_y += from.force_y;
}

void add_into(Vec2& to, const PlainVec2& from) {
  to.x() += from.x;
  to.y() += from.y;
}

// What goes into a halo message: trivially copyable values (Eigen's vectors are not).
const NodeSums& plain(const NodeSums& s) {
  return s;
}
PlainVec2 plain(const Vec2& v) {
  return {v.x(), v.y()};
}

/// Adds the wall time of its scope to `seconds` (the benchmarks' exchange time).
class ExchangeTimer {
 public:
  explicit ExchangeTimer(double& seconds)
      : seconds_(seconds), start_(std::chrono::steady_clock::now()) {}
  ~ExchangeTimer() {
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  ExchangeTimer(const ExchangeTimer&) = delete;
  ExchangeTimer& operator=(const ExchangeTimer&) = delete;

 private:
  double& seconds_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

template <class T>
void Subdomain::sum_shared_columns(const GridGeometry& grid, int active_begin, int active_end,
                                   std::span<T> values) const {
  if (!ranks_.distributed()) return;
  const ExchangeTimer timer(exchange_seconds);
  const auto rows = static_cast<std::size_t>(grid.node_rows());
  const int rank = ranks_.rank();
  const bool has_left = rank > 0, has_right = rank < ranks_.size() - 1;
  // The three node columns around a cut at cell column c are storage columns c … c + 2.
  constexpr int width = 3;
  using Plain = std::decay_t<decltype(plain(values[0]))>;
  const auto band = [&](int first) {
    std::vector<Plain> out(width * rows, Plain{});
    for (int column = first; column < first + width; ++column) {
      if (column < active_begin || column >= active_end) continue;
      const auto at = static_cast<std::size_t>(column) * rows;
      const auto to = static_cast<std::size_t>(column - first) * rows;
      for (std::size_t row = 0; row < rows; ++row) out[to + row] = plain(values[at + row]);
    }
    return out;
  };
  const std::vector<Plain> left = has_left ? band(first_cell()) : std::vector<Plain>{};
  const std::vector<Plain> right = has_right ? band(end_cell()) : std::vector<Plain>{};
  const auto as_bytes = [](const std::vector<Plain>& v) {
    return std::as_bytes(std::span<const Plain>(v.data(), v.size()));
  };
  const auto from_right =
      ranks_.exchange(has_left ? rank - 1 : -1, as_bytes(left), has_right ? rank + 1 : -1);
  const auto from_left =
      ranks_.exchange(has_right ? rank + 1 : -1, as_bytes(right), has_left ? rank - 1 : -1);
  bytes_sent += static_cast<std::int64_t>((left.size() + right.size()) * sizeof(Plain));
  const auto add = [&](std::span<const std::byte> received, int first) {
    if (received.empty()) return;
    if (received.size() != width * rows * sizeof(Plain))
      throw Error("mpm: a halo message of {} bytes, expected {}", received.size(),
                  width * rows * sizeof(Plain));
    const std::vector<Plain> theirs = Ranks::values_of<Plain>(received);
    for (int column = first; column < first + width; ++column) {
      if (column < active_begin || column >= active_end) continue;
      const auto at = static_cast<std::size_t>(column) * rows;
      const auto from = static_cast<std::size_t>(column - first) * rows;
      for (std::size_t row = 0; row < rows; ++row) add_into(values[at + row], theirs[from + row]);
    }
  };
  add(from_left, first_cell());
  add(from_right, end_cell());
}

void Subdomain::sum_shared(const GridGeometry& grid, int active_begin, int active_end,
                           std::span<NodeSums> sums) const {
  sum_shared_columns(grid, active_begin, active_end, sums);
}

void Subdomain::sum_shared(const GridGeometry& grid, int active_begin, int active_end,
                           std::span<Vec2> momenta) const {
  sum_shared_columns(grid, active_begin, active_end, momenta);
}

void Subdomain::check_reach(const GridGeometry& grid, int active_begin, int active_end) const {
  if (!ranks_.distributed() || active_end <= active_begin) return;
  const int rank = ranks_.rank();
  const int low = rank == 0 ? 0 : first_cell();
  const int high = rank == ranks_.size() - 1 ? grid.node_columns() : end_cell() + 3;
  if (active_begin < low || active_end > high) {
    throw Error(
        "mpm: rank {}'s particles reach node columns {}–{}, beyond the columns it shares with "
        "its neighbours ({}–{}): a particle domain larger than a cell",
        rank, active_begin - 1, active_end - 2, low - 1, high - 2);
  }
}

std::size_t Subdomain::migrate(Particles& particles, std::size_t active, const GridGeometry& grid,
                               const PackedLayout& layout, bool& changed) const {
  changed = false;
  if (!ranks_.distributed()) return active;
  const ExchangeTimer timer(exchange_seconds);
  const int rank = ranks_.rank();
  std::vector<std::size_t> to_left, to_right;
  std::vector<char> keep(particles.count(), 1);
  for (std::size_t p = 0; p < active; ++p) {
    const Vec2& x = particles.coordinates[p];
    if (!x.allFinite()) continue;  // stays: locating it reports the instability
    const int owner = cuts_.owner_of_column(cell_column_of(grid, x));
    if (owner == rank) continue;
    if (owner == rank - 1) {
      to_left.push_back(p);
    } else if (owner == rank + 1) {
      to_right.push_back(p);
    } else {
      throw Error(
          "instability: particle {} (id {}) at ({:.3f}, {:.3f}) m crossed a whole slab in one "
          "step (from rank {} to rank {})",
          p, particles.id[p], x.x(), x.y(), rank, owner);
    }
    keep[p] = 0;
  }
  std::vector<std::byte> left_bytes, right_bytes;
  pack_particles(particles, to_left, layout, left_bytes);
  pack_particles(particles, to_right, layout, right_bytes);
  const bool has_left = rank > 0, has_right = rank < ranks_.size() - 1;
  auto from_right =
      ranks_.exchange(has_left ? rank - 1 : -1, left_bytes, has_right ? rank + 1 : -1);
  auto from_left =
      ranks_.exchange(has_right ? rank + 1 : -1, right_bytes, has_left ? rank - 1 : -1);
  bytes_sent += static_cast<std::int64_t>(left_bytes.size() + right_bytes.size());
  if (to_left.empty() && to_right.empty() && from_left.empty() && from_right.empty()) return active;
  changed = true;
  return regroup(particles, active, std::move(keep),
                 std::vector<std::vector<std::byte>>{std::move(from_left), std::move(from_right)},
                 layout);
}

bool Subdomain::rebalance(Particles& particles, std::size_t& active, const GridGeometry& grid,
                          const PackedLayout& layout) {
  if (!ranks_.distributed()) return false;
  const ExchangeTimer timer(exchange_seconds);
  const auto largest = ranks_.max(static_cast<std::int64_t>(active));
  const double mean = ranks_.sum(static_cast<double>(active)) / ranks_.size();
  if (!(static_cast<double>(largest) > (1.0 + rebalance_share) * mean)) return false;
  std::vector<std::int64_t> histogram = particles_per_column(particles, active, grid);
  ranks_.sum(std::span<std::int64_t>(histogram));
  SlabCuts cuts = SlabCuts::balanced(histogram, ranks_.size());
  if (cuts.begin == cuts_.begin) return false;
  // Every particle to its new owner; the kept ones first, then the arrivals in rank order.
  const int rank = ranks_.rank();
  std::vector<std::vector<std::size_t>> leaving(static_cast<std::size_t>(ranks_.size()));
  std::vector<char> keep(particles.count(), 1);
  for (std::size_t p = 0; p < active; ++p) {
    const int owner = cuts.owner_of_column(cell_column_of(grid, particles.coordinates[p]));
    if (owner == rank) continue;
    leaving[static_cast<std::size_t>(owner)].push_back(p);
    keep[p] = 0;
  }
  std::vector<std::vector<std::byte>> outgoing(leaving.size());
  for (std::size_t r = 0; r < leaving.size(); ++r) {
    pack_particles(particles, leaving[r], layout, outgoing[r]);
    bytes_sent += static_cast<std::int64_t>(outgoing[r].size());
  }
  active = regroup(particles, active, std::move(keep), ranks_.all_to_all(outgoing), layout);
  cuts_ = std::move(cuts);
  ++recuts;
  return true;
}

int HeldRows::holder(std::size_t index, std::size_t part_active) const {
  // The part's active rows are the file's active rows from first_row on; its frozen rows
  // follow every rank's active ones.
  const bool is_frozen = index >= part_active;
  const std::vector<std::int64_t>& rows = is_frozen ? frozen : active;
  std::int64_t row = static_cast<std::int64_t>(first_row + index);
  if (is_frozen) row -= std::accumulate(active.begin(), active.end(), std::int64_t{0});
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (row < rows[r]) return static_cast<int>(r);
    row -= rows[r];
  }
  throw Error("mpm: particle row {} is beyond the rows the ranks held", first_row + index);
}

std::size_t Subdomain::scatter(Particles& particles, std::size_t frozen, const GridGeometry& grid,
                               const PackedLayout& layout, const HeldRows* held) const {
  const std::size_t active = particles.count() - std::min(frozen, particles.count());
  if (!ranks_.distributed()) return active;
  const ExchangeTimer timer(exchange_seconds);
  const auto n = static_cast<std::size_t>(ranks_.size());
  std::vector<std::vector<std::size_t>> to(n), to_frozen(n);
  for (std::size_t p = 0; p < particles.count(); ++p) {
    const bool is_frozen = p >= active;
    const int owner = held != nullptr ? held->holder(p, active)
                      : is_frozen
                          ? 0
                          : cuts_.owner_of_column(cell_column_of(grid, particles.coordinates[p]));
    (is_frozen ? to_frozen : to)[static_cast<std::size_t>(owner)].push_back(p);
  }
  // This rank's own particles travel too (a message to itself), so that every rank ends
  // with its particles in the order of the parts, which is the order of the file.
  std::vector<std::vector<std::byte>> outgoing(n), outgoing_frozen(n);
  for (std::size_t r = 0; r < n; ++r) {
    pack_particles(particles, to[r], layout, outgoing[r]);
    pack_particles(particles, to_frozen[r], layout, outgoing_frozen[r]);
  }
  to.clear();
  to_frozen.clear();
  // The part goes before the arrivals come: a rank holds both at once only as bytes.
  particles.resize(0);
  particles.affine_velocity.clear();
  particles.shrink_to_fit();
  const auto arrivals = ranks_.all_to_all(outgoing);
  outgoing.clear();
  const auto frozen_arrivals = ranks_.all_to_all(outgoing_frozen);
  outgoing_frozen.clear();
  for (const auto& bytes : arrivals) unpack_particles(bytes, layout, particles);
  const std::size_t now_active = particles.count();
  for (const auto& bytes : frozen_arrivals) unpack_particles(bytes, layout, particles);
  return now_active;
}

std::optional<std::int64_t> duplicate_id(const Particles& particles, const Ranks& ranks) {
  // Each id to rank id mod N, which sorts the ids it receives: one pass over the ids
  // with one all-to-all, wherever the duplicates are.
  const auto n = static_cast<std::size_t>(ranks.size());
  std::vector<std::vector<std::int64_t>> buckets(n);
  for (const std::int64_t id : particles.id)
    buckets[static_cast<std::size_t>(id >= 0 ? id % ranks.size() : 0)].push_back(id);
  std::vector<std::vector<std::byte>> outgoing(n);
  for (std::size_t r = 0; r < n; ++r) {
    const auto bytes = Ranks::bytes_of(std::span<const std::int64_t>(buckets[r]));
    outgoing[r].assign(bytes.begin(), bytes.end());
  }
  std::vector<std::int64_t> mine;
  for (const auto& bytes : ranks.all_to_all(outgoing)) {
    const auto ids = Ranks::values_of<std::int64_t>(bytes);
    mine.insert(mine.end(), ids.begin(), ids.end());
  }
  std::sort(mine.begin(), mine.end());
  const auto twin = std::adjacent_find(mine.begin(), mine.end());
  // The smallest duplicate of all ranks (−1: none), the same on every rank.
  const std::int64_t found = twin == mine.end() ? std::numeric_limits<std::int64_t>::max() : *twin;
  const std::int64_t smallest = -ranks.max(-found);
  if (smallest == std::numeric_limits<std::int64_t>::max()) return std::nullopt;
  return smallest;
}

std::size_t keep_part(Particles& particles, std::size_t frozen, const Ranks& ranks) {
  const std::size_t n = particles.count();
  const RowSpan rows = ranks.part().rows(n);
  std::vector<char> keep(n, 0);
  std::fill(keep.begin() + static_cast<std::ptrdiff_t>(rows.first),
            keep.begin() + static_cast<std::ptrdiff_t>(rows.end), 1);
  compact(particles, keep);
  return rows.last_rows_within(n, frozen);
}

}  // namespace slide::mpm
