#include "fem/recorders.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/io/atomic_file.hpp"
#include "fem/pore_fluid.hpp"

namespace slide::fem {

namespace {

Index nearest_node(const FemModel& model, const Vec2& point) {
  Index best = 0;
  double distance = std::numeric_limits<double>::infinity();
  for (Index n = 0; n < model.node_count(); ++n) {
    const double d = (model.mesh.nodes[static_cast<std::size_t>(n)] - point).squaredNorm();
    if (d < distance) {
      distance = d;
      best = n;
    }
  }
  return best;
}

Index nearest_element(const FemModel& model, const Vec2& point) {
  Index best = 0;
  double distance = std::numeric_limits<double>::infinity();
  const int npe = model.nodes_per_element;
  for (Index e = 0; e < model.element_count(); ++e) {
    Vec2 centroid = Vec2::Zero();
    for (int k = 0; k < npe; ++k) {
      centroid += model.mesh.nodes[static_cast<std::size_t>(
          model.mesh.connectivity[static_cast<std::size_t>(e * npe + k)])];
    }
    const double d = (centroid / npe - point).squaredNorm();
    if (d < distance) {
      distance = d;
      best = e;
    }
  }
  return best;
}

void append(std::string& text, double value) {
  fmt::format_to(std::back_inserter(text), ",{}", value);
}

/// The nodes of a recorder's node set, or Error naming the recorder.
std::vector<Index> node_set_nodes(const FemModel& model, const RecorderSpec& spec) {
  for (const NodeSet& set : model.mesh.node_sets) {
    if (set.name == spec.node_set) return set.nodes;
  }
  throw Error("fem.recorders \"{}\": the mesh has no node set \"{}\"", spec.name, spec.node_set);
}

/// The CSV header of a recorder's columns.
std::string header(const std::vector<Index>& nodes, const std::vector<Index>& elements,
                   bool water) {
  std::string text = "time";
  if (!nodes.empty()) {
    for (const char* q : {"ux", "uy", "vx", "vy", "ax", "ay"}) text += fmt::format(",base_{}", q);
    for (const Index n : nodes) {
      for (const char* suffix : {"", "_rel"}) {
        for (const char* q : {"ux", "uy", "vx", "vy", "ax", "ay"}) {
          text += fmt::format(",n{}_{}{}", n, q, suffix);
        }
      }
      if (water) text += fmt::format(",n{}_p,n{}_dp", n, n);
    }
  }
  for (const Index e : elements) {
    for (const char* q : {"sxx", "syy", "szz", "sxy", "exx", "eyy", "ezz", "gxy"}) {
      text += fmt::format(",e{}_{}", e, q);
    }
    if (water) text += fmt::format(",e{}_p,e{}_ru", e, e);
  }
  return text + '\n';
}

/// Per element the means over its Gauss points of σ and ε, and with pore water p and r_u.
void append_elements(const FemModel& model, const FemState& state,
                     const std::vector<Index>& elements, std::string& rows) {
  const int n_gauss = model.gauss_per_element();
  for (const Index e : elements) {
    Vec4 stress = Vec4::Zero(), strain = Vec4::Zero();
    for (int g = 0; g < n_gauss; ++g) {
      const auto gp = static_cast<std::size_t>(e * n_gauss + g);
      stress += state.stress[gp];
      strain += state.strain[gp];
    }
    for (int i = 0; i < 4; ++i) append(rows, stress[i] / n_gauss);
    for (int i = 0; i < 4; ++i) append(rows, strain[i] / n_gauss);
    if (model.fluid.active()) {
      const auto [p, ratio] = element_pore_water(model, state, e);
      append(rows, p);
      append(rows, ratio);
    }
  }
}

/// The drained faces whose two nodes are both in `nodes`.
std::vector<std::size_t> faces_of_set(const FemModel& model, const std::vector<Index>& nodes) {
  std::vector<std::uint8_t> in_set(static_cast<std::size_t>(model.node_count()), 0);
  for (const Index n : nodes) in_set[static_cast<std::size_t>(n)] = 1;
  std::vector<std::size_t> faces;
  for (std::size_t f = 0; f < model.fluid.faces.size(); ++f) {
    const auto& side = model.fluid.faces[f].side;
    if (side[0] >= 0 && in_set[static_cast<std::size_t>(side[0])] &&
        in_set[static_cast<std::size_t>(side[1])]) {
      faces.push_back(f);
    }
  }
  return faces;
}

}  // namespace

Recorders::Recorders(const FemModel& model, const std::vector<RecorderSpec>& specs,
                     std::filesystem::path folder, const GroundMotion* motion,
                     std::vector<Index> base_nodes)
    : model_(model),
      folder_(std::move(folder)),
      motion_(motion),
      base_nodes_(std::move(base_nodes)) {
  for (const RecorderSpec& spec : specs) {
    // The file name, <name>.csv, within what a file system takes (255 bytes).
    if (spec.name.size() > max_name_bytes) {
      throw Error("fem.recorders \"{}…\": the name has {} bytes, at most {} (it names a file)",
                  spec.name.substr(0, 40), spec.name.size(), max_name_bytes);
    }
    Recorder r;
    r.name = spec.name;
    r.every = spec.every;
    for (const Vec2& p : spec.points) r.nodes.push_back(nearest_node(model, p));
    if (!spec.node_set.empty()) r.nodes = node_set_nodes(model, spec);
    for (const Vec2& p : spec.elements) r.elements.push_back(nearest_element(model, p));
    r.header = header(r.nodes, r.elements, model.fluid.active());
    if (!spec.node_set.empty() && model.fluid.active()) {
      r.drained_faces = faces_of_set(model, r.nodes);
      r.header.back() = ',';
      r.header += "outflow\n";
    }
    recorders_.push_back(std::move(r));
  }
}

void Recorders::bound(double duration, double step, std::size_t limit) {
  double bytes = 0.0;
  for (Recorder& r : recorders_) {
    // A cadence below the step records at every step, as a cadence of 0 does (and a
    // cadence of 1e-15 s no longer spins on the clock's last digits).
    if (r.every < step) r.every = 0.0;
    const double rows = std::floor(duration / std::max(r.every, step)) + 2.0;
    const auto columns = static_cast<double>(std::ranges::count(r.header, ',') + 1);
    bytes += rows * columns * bytes_per_value;
  }
  if (bytes > static_cast<double>(limit)) {
    throw Error(
        "fem.recorders would hold and write about {:.3g} GB over the run ({:.4g} s in steps of "
        "{:.3g} s), above the {:.3g} GB the project allows: give them a coarser `every` or "
        "fewer nodes and elements",
        bytes / 1e9, duration, step, static_cast<double>(limit) / 1e9);
  }
}

void Recorders::resume(double time, const Logger& logger) {
  for (Recorder& r : recorders_) {
    const auto path = folder_ / (r.name + ".csv");
    std::ifstream in(path);
    if (!in) {
      logger.warning("{}: not found, the recorder starts at t = {:.3f} s", path.string(), time);
      r.next = time;
      continue;
    }
    std::string line;
    std::getline(in, line);
    if (line + '\n' != r.header) {
      logger.warning("{}: other columns than the case's recorder, started again at t = {:.3f} s",
                     path.string(), time);
      r.next = time;
      continue;
    }
    double last = -std::numeric_limits<double>::infinity();
    while (std::getline(in, line)) {
      double t = 0.0;
      try {
        t = std::stod(line.substr(0, line.find(',')));
      } catch (const std::exception&) {
        break;  // a row a killed run left unfinished
      }
      if (t > time + 1e-9 * std::max(1.0, time)) break;
      r.rows += line + '\n';
      last = t;
    }
    r.next = r.every > 0.0 && std::isfinite(last) ? last + r.every : time;
  }
}

void Recorders::record(const FemState& state, double dt) {
  const double t = state.time;
  const auto due = [&](const Recorder& r) {
    return !(r.every > 0.0) || t >= r.next - 1e-9 * std::max(1.0, t);
  };
  if (std::ranges::none_of(recorders_, due)) return;
  // The base's fields as the nodes' are formed: u at t, v over the step, a at t − dt.
  Vec2 base_u = Vec2::Zero(), base_v = Vec2::Zero(), base_a = Vec2::Zero();
  if (motion_ != nullptr && dt > 0.0) {
    base_u = motion_->displacement(t);
    base_v = motion_->step_velocity(t - dt, dt);
    base_a = motion_->acceleration(t - dt);
  } else if (!base_nodes_.empty()) {
    for (const Index n : base_nodes_) {
      base_u += state.displacement[static_cast<std::size_t>(n)];
      base_v += state.velocity[static_cast<std::size_t>(n)];
      base_a += state.acceleration[static_cast<std::size_t>(n)];
    }
    const double share = 1.0 / static_cast<double>(base_nodes_.size());
    base_u *= share;
    base_v *= share;
    base_a *= share;
  }
  for (Recorder& r : recorders_) {
    if (!due(r)) continue;
    while (r.every > 0.0 && r.next <= t + 1e-9 * std::max(1.0, t)) r.next += r.every;
    fmt::format_to(std::back_inserter(r.rows), "{}", t);
    if (!r.nodes.empty()) {
      for (const Vec2* q : {&base_u, &base_v, &base_a}) {
        append(r.rows, q->x());
        append(r.rows, q->y());
      }
      for (const Index node : r.nodes) {
        const auto n = static_cast<std::size_t>(node);
        const std::array<Vec2, 3> absolute{state.displacement[n], state.velocity[n],
                                           state.acceleration[n]};
        for (const Vec2& q : absolute) {
          append(r.rows, q.x());
          append(r.rows, q.y());
        }
        const std::array<Vec2, 3> relative{absolute[0] - base_u, absolute[1] - base_v,
                                           absolute[2] - base_a};
        for (const Vec2& q : relative) {
          append(r.rows, q.x());
          append(r.rows, q.y());
        }
        if (model_.fluid.active()) {
          append(r.rows, state.pore_pressure[n]);
          append(r.rows, state.pore_pressure[n] - state.static_pore_pressure[n]);
        }
      }
    }
    append_elements(model_, state, r.elements, r.rows);
    if (r.drained_faces) {
      double outflow = 0.0;
      for (const std::size_t f : *r.drained_faces) {
        outflow += drained_outflow(model_, state, model_.fluid.faces[f]);
      }
      append(r.rows, outflow);
    }
    r.rows += '\n';
  }
}

void Recorders::write() const {
  for (const Recorder& r : recorders_) {
    write_text_atomically(folder_ / (r.name + ".csv"), r.header + r.rows);
  }
}

std::string Recorders::describe() const {
  std::string text;
  for (const Recorder& r : recorders_) {
    if (!text.empty()) text += "; ";
    text += fmt::format("{}: {} nodes, {} elements, {}", r.name, r.nodes.size(), r.elements.size(),
                        r.every > 0.0 ? fmt::format("every {} s", r.every) : "every step");
  }
  return text;
}

}  // namespace slide::fem
