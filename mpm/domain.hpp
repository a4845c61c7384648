// mpm-solve on several ranks (docs/parallel.md): the grid's cell columns cut into one
// slab per rank, each rank owning the particles whose cell is in its slab.
//
// A particle in cell column c touches node columns c − 1 … c + 2 (uGIMP with a domain of
// at most a cell; linear hats c … c + 1). Across the cut at column c between ranks r − 1
// and r, both ranks therefore scatter into node columns c − 1, c and c + 1, and only
// there: each step every rank sends its sums of those three columns to the neighbour
// and adds what it receives (mass, momentum, force, and MUSL's re-projected momenta),
// so that a shared node holds the same full sum on both sides (two addends: a + b = b + a
// exactly). A slab of at least three cells keeps the two cuts of a rank apart, so no node
// is shared by three ranks. Cells are never shared: the volumetric smoothing's cell
// averages need no exchange.
//
// After the position update (at the start of the next step, once the grid has moved
// with a shaken base) particles whose cell left the slab go to the neighbour that owns
// it; the Courant step keeps a particle from crossing a whole slab in one step, and a
// particle that did is an instability. Every `sort_interval` steps the ranks compare
// their particle counts; when the largest exceeds the mean by more than
// `rebalance_share`, the slabs are re-cut from the global particle count per cell column
// and the particles sent to their new owners. The cuts depend on the counts only, so a
// run on N ranks is the same run every time.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/base/ranks.hpp"
#include "common/physics/particles.hpp"
#include "mpm/grid.hpp"

namespace slide::mpm {

/// The narrowest slab, in cells (see the header comment).
inline constexpr int min_slab_cells = 3;

/// Cell columns [begin[r], begin[r + 1]) belong to rank r.
struct SlabCuts {
  std::vector<int> begin;

  int ranks() const { return static_cast<int>(begin.size()) - 1; }
  int owner_of_column(int cell_column) const;
  /// Throws Error unless the cuts cover `columns` cell columns in slabs of at least
  /// min_slab_cells.
  void check(int columns) const;
  /// Cuts that give each of `ranks` slabs about the same number of particles, from the
  /// count per cell column, with every slab at least min_slab_cells wide. Throws Error
  /// when the grid is too narrow for that many ranks.
  static SlabCuts balanced(std::span<const std::int64_t> particles_per_column, int ranks);
};

/// Share by which the largest rank's particle count may exceed the mean before a re-cut:
/// a re-cut moves about that share of the particles once, while an imbalance of that share
/// costs it on every step until the next re-cut, so re-cutting much earlier pays little.
inline constexpr double default_rebalance_share = 0.1;

/// Which rows of a checkpoint each rank held when it was written: every rank's active
/// rows in rank order, then every rank's frozen rows (the order of the file's rows), and
/// where this rank's part of the rows begins. A particle that crossed a cut in the step
/// before the checkpoint is still held by the rank it left (ranks migrate at the start of
/// a step), so a restart gives rows back to their holders, not to the slab of their cell.
struct HeldRows {
  std::vector<std::int64_t> active;  ///< per rank
  std::vector<std::int64_t> frozen;  ///< per rank
  std::size_t first_row = 0;         ///< of this rank's part of the file

  /// The rank that held the part's particle `index` (`part_active` of the part active).
  int holder(std::size_t index, std::size_t part_active) const;
};

/// How a run is cut into slabs: balanced on the particles unless `cuts` are given (tests
/// that need particles to cross fixed cuts, restarts), re-cut at `rebalance_share`
/// (infinity: never). With `held`, each particle goes back to the rank that held it.
struct Decomposition {
  std::optional<SlabCuts> cuts;
  std::optional<HeldRows> held;
  double rebalance_share = default_rebalance_share;
};

/// Particles per cell column of the grid, of particles [0, count).
std::vector<std::int64_t> particles_per_column(const Particles& particles, std::size_t count,
                                               const GridGeometry& grid);

/// The cell column a particle's owner is found by (the half-cell margins count as the
/// edge columns, as GridGeometry::cell_of).
int cell_column_of(const GridGeometry& grid, const Vec2& x);

/// What a packed particle holds besides the fields every particle has: its multi-yield
/// surface stresses and, in an APIC run, its affine velocity. The run's settings give it,
/// not the particles: a rank whose particles all left holds no affine field to tell.
struct PackedLayout {
  std::size_t surfaces = 0;
  bool affine = false;
  /// The saturated transfer's fields (Δp, r_u,max, σ′v0, p′₀, liquefied) travel too.
  bool pore_water = false;
  /// Bytes one packed particle takes.
  std::size_t bytes() const;
};

/// Particles as bytes: every field of the rows `indices`, appended to `bytes`; and back,
/// appended to the particles. Both throw Error when the particles do not fit `layout`.
void pack_particles(const Particles& particles, std::span<const std::size_t> indices,
                    const PackedLayout& layout, std::vector<std::byte>& bytes);
std::size_t unpack_particles(std::span<const std::byte> bytes, const PackedLayout& layout,
                             Particles& particles);

/// Of a particle set every rank holds whole, keeps this rank's part, which is what
/// MpmSolver::distribute takes: rows [⌊r n/N⌋, ⌊(r + 1) n/N⌋) of the n rows, the way a
/// particle file is read in parts (read_particle_checkpoint). The last `frozen` rows of
/// the set are frozen. Returns how many of them are in the part (they stay last). Not
/// collective.
std::size_t keep_part(Particles& particles, std::size_t frozen, const Ranks& ranks);

/// The smallest id that two particles share, on whichever ranks they are (collective).
std::optional<std::int64_t> duplicate_id(const Particles& particles, const Ranks& ranks);

/// This rank's slab and its exchanges with the other ranks.
class Subdomain {
 public:
  Subdomain(const Ranks& ranks, SlabCuts cuts);

  const Ranks& ranks() const { return ranks_; }
  const SlabCuts& cuts() const { return cuts_; }
  int first_cell() const { return cuts_.begin[static_cast<std::size_t>(ranks_.rank())]; }
  int end_cell() const { return cuts_.begin[static_cast<std::size_t>(ranks_.rank()) + 1]; }
  /// Node columns (storage order, GridGeometry::node_column) whose nodes this rank
  /// counts as its own in sums over nodes (the constraints' work): those of its cells'
  /// lower-left corners, and on the last rank the grid's right edge and ghost column.
  std::pair<int, int> own_node_columns(const GridGeometry& grid) const;

  /// Adds the neighbours' sums of the shared node columns to this rank's (collective).
  /// `active_*`: the node columns this rank's particles touched (the others hold stale
  /// values: sent as zeros, left alone).
  void sum_shared(const GridGeometry& grid, int active_begin, int active_end,
                  std::span<NodeSums> sums) const;
  void sum_shared(const GridGeometry& grid, int active_begin, int active_end,
                  std::span<Vec2> momenta) const;
  /// Throws Error when particles touch node columns beyond the shared ones (a particle
  /// domain larger than a cell).
  void check_reach(const GridGeometry& grid, int active_begin, int active_end) const;

  /// Hands the active particles [0, active) whose cell left this slab to the neighbour
  /// that owns it and takes the neighbours' (collective). The others keep their order;
  /// arrivals follow them (left neighbour's first), ahead of the frozen particles.
  /// Returns the new active count; `changed` tells whether any particle came or went.
  std::size_t migrate(Particles& particles, std::size_t active, const GridGeometry& grid,
                      const PackedLayout& layout, bool& changed) const;

  /// Every `sort_interval` steps: re-cuts the slabs when the largest active count exceeds
  /// the mean by more than `rebalance_share` and sends every particle to its new owner
  /// (collective). Returns true when it re-cut; `active` is updated.
  bool rebalance(Particles& particles, std::size_t& active, const GridGeometry& grid,
                 const PackedLayout& layout);

  /// Sends every particle of this rank's part of the whole set (keep_part; the last
  /// `frozen` frozen) to its owner: the rank that `held` it when given, else an active one
  /// to the rank whose slab holds its cell and a frozen one to rank 0 (collective). Every
  /// rank ends with its particles in the order of the parts, which is the order of the
  /// whole set, the frozen ones last. Returns the new active count.
  std::size_t scatter(Particles& particles, std::size_t frozen, const GridGeometry& grid,
                      const PackedLayout& layout, const HeldRows* held = nullptr) const;

  /// Share by which the largest rank's particle count may exceed the mean before a re-cut.
  double rebalance_share = default_rebalance_share;
  /// Re-cuts done so far (logged at the end of the run).
  std::int64_t recuts = 0;
  /// Bytes sent to the other ranks so far by the steps (halo, migration, re-cuts; not the
  /// scatter at the start), for the log and the benchmarks.
  mutable std::int64_t bytes_sent = 0;
  /// Wall time spent in the halo sums, migrations and re-cuts so far, waiting for the
  /// neighbours included (what a slower neighbour costs shows here), for the benchmarks.
  mutable double exchange_seconds = 0.0;

 private:
  template <class T>
  void sum_shared_columns(const GridGeometry& grid, int active_begin, int active_end,
                          std::span<T> values) const;

  const Ranks& ranks_;
  SlabCuts cuts_;
};

}  // namespace slide::mpm
