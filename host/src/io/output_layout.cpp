// The output file's layout (docs/user-guide.md, "Output"): every group, attribute and series,
// created once when the file is made; and /parameters/pair_models.
#include <noether/output.hpp>
#include <noether/particles.hpp>
#include <noether/version.hpp>

#include "io/h5.hpp"
#include "io/frame_schema.hpp"
#include "io/h5.hpp"
#include "io/checksum.hpp"
#include "run/binary_pair.hpp"
#include "io/output_impl.hpp"
#include "run/spin_state_tracker.hpp"

#include <cmath>
#include <limits>

namespace noether {

namespace fs = std::filesystem;
using namespace noether::io;

namespace {

// /parameters/shapes/<body>/{vertices [n][3], faces [m][3]}: a polyhedron in its body frame.
void write_mesh(hid_t group, const Mesh& mesh, const Units& units) {
  const hsize_t n = static_cast<hsize_t>(mesh.vertices.cols()), m = mesh.faces.size();
  {
    const hsize_t dims[2] = {n, 3};
    const io::H5Handle space(H5Screate_simple(2, dims, nullptr));
    const io::H5Handle d(check_id(H5Dcreate2(group, "vertices", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT,
                                             H5P_DEFAULT), "vertices"));
    check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, mesh.vertices.data()), "vertices");
    string_attribute(d, "unit", units.of_length());
    string_attribute(d, "description", "the polyhedron's vertices in the body frame (centre of mass, principal axes) "
                                       "[vertex][xyz]");
  }
  std::vector<int> faces;
  for (const auto& f : mesh.faces) faces.insert(faces.end(), f.begin(), f.end());
  const hsize_t dims[2] = {m, 3};
  const io::H5Handle space(H5Screate_simple(2, dims, nullptr));
  const io::H5Handle d(
      check_id(H5Dcreate2(group, "faces", H5T_NATIVE_INT, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "faces"));
  if (m) check(H5Dwrite(d, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, faces.data()), "faces");
  string_attribute(d, "description", "the polyhedron's triangles: 0-based vertex indices, counter-clockwise seen "
                                     "from outside [face][3]");
}

}  // namespace

void H5Writer::create_layout(const Scene& scene) {
  Impl& m = *impl_;
  const OutputOptions& options = m.options;
  const System& sys = scene.system;
  m.n_bodies = sys.size();
  m.n_rigid = sys.rigid_count();
  m.system = sys;
  m.largest_moment_axes.clear();
  for (std::size_t k = 0; k < sys.rigid_count(); ++k)
    m.largest_moment_axes.push_back(largest_moment_axis(sys.body(sys.body_of_rigid(k)).inertia));
  if (const auto pair = binary_pair(sys)) {
    m.primary = static_cast<std::ptrdiff_t>(pair->primary);
    m.secondary = static_cast<std::ptrdiff_t>(pair->secondary);
  }
  // Every series is allocated for the frames the run will write, up to a budget; a run that
  // writes more grows them (in doubling steps, each flushed at once).
  double frame_bytes = 8.0 * static_cast<double>(io::checkpointed_series().size());  // the checksums
  m.layout = io::layout_of(sys, options.checkpoint_width, options.stm_columns, options.sensitivity_names.size(),
                           options.force_names.size(), options.feature_series, options.feature_fields.size());
  for (const auto& declared : options.feature_series) {  // each a row of the schema that a feature fills
    const auto schema = io::frame_schema();
    if (std::none_of(schema.begin(), schema.end(),
                     [&](const io::FrameQuantity& q) { return q.fill.by_feature && declared.name == q.name; }))
      throw std::logic_error("a run feature's series '" + declared.name +
                             "' is not a row of the frame schema filled by a feature (io/frame_schema.cpp)");
  }
  for (const auto& q : io::frame_schema()) {
    if (!io::present(q, m.layout)) continue;
    double bytes = 8.0;
    for (const auto d : io::frame_shape(q, m.layout))
      bytes *= static_cast<double>(d);
    frame_bytes += bytes;
  }

  const double budget = std::max(1.0, std::floor(options.preallocate_bytes / frame_bytes));
  m.allocated = static_cast<hsize_t>(
      std::min(options.expected_frames > 0 ? static_cast<double>(options.expected_frames) : 1024.0, budget));

  const io::H5Handle h5md(make_group(m.file, "h5md"));
  numeric_attribute<int>(h5md, "version", H5T_NATIVE_INT, {1, 1});
  const io::H5Handle creator(make_group(h5md, "creator"));
  string_attribute(creator, "name", "noether");
  string_attribute(creator, "version", NOETHER_VERSION);

  const io::H5Handle parameters(make_group(m.file, "parameters"));
  string_attribute(parameters, "scene_file", scene.file);
  // Where the scene was, so that a continued run finds its shape files from any folder.
  std::error_code ec;
  const fs::path absolute = scene.file.empty() ? fs::path() : fs::absolute(scene.file, ec);
  const std::string scene_path = ec ? scene.file : absolute.string();
  string_attribute(parameters, "scene_path", scene_path);
  string_dataset(parameters, "scene", scene.text, "the scene file's text, as given");
  string_dataset(parameters, "scene_as_run", scene_as_run(scene),
                 "the scene as run: after the --set overrides (YAML)");
  std::string overrides;
  for (const auto& o : scene.overrides) overrides += (overrides.empty() ? "" : "\n") + o;
  string_attribute(parameters, "overrides", overrides);
  // What a continued run rebuilds its scene from, checksummed (io/run_record.cpp).
  numeric_attribute<std::uint64_t>(parameters, "checksum", H5T_NATIVE_UINT64,
                                   {io::scene_checksum(scene.text, scene_path, overrides, options.custom_potential)});
  std::string potentials;
  for (const auto& p : scene.potentials) potentials += (potentials.empty() ? "" : "+") + p.plugin;
  string_attribute(parameters, "potential", options.custom_potential ? "python (given in code, not the scene's)" : potentials);
  numeric_attribute<int>(parameters, "custom_potential", H5T_NATIVE_INT, {options.custom_potential ? 1 : 0});
  string_attribute(parameters, "integrator", scene.integrator.plugin);
  if (!options.force_names.empty()) {  // the columns of /observables/force_balance, in order
    std::string names;
    for (const auto& n : options.force_names) names += (names.empty() ? "" : "\n") + n;
    string_attribute(parameters, "forces", names);
  }
  scalar_attribute(parameters, "G", sys.G());
  string_attribute(parameters, "units", scene.units.describe());
  string_attribute(parameters, "unit_length", scene.units.of_length());
  string_attribute(parameters, "unit_mass", scene.units.of_mass());
  string_attribute(parameters, "unit_time", scene.units.of_time());
  string_attribute(parameters, "unit_G", scene.units.of_G());
  scalar_attribute(parameters, "t_end", scene.run.t_end);
  scalar_attribute(parameters, "output_every", scene.run.output_every);
  // Bodies with a solid shape: what it is and how its mesh was placed in the body frame
  // (x_file = offset + rotation · x_body).
  io::H5Handle shapes;
  for (const auto& b : sys.bodies()) {
    if (!b.solid) continue;
    if (!shapes.valid()) shapes = io::H5Handle(make_group(parameters, "shapes"));
    const io::H5Handle g(make_group(shapes, b.name.c_str()));
    string_attribute(g, "kind", b.solid->kind == Solid::Kind::Ellipsoid ? "ellipsoid" : "polyhedron");
    string_attribute(g, "description", b.solid->describe());
    numeric_attribute<double>(g, "density", H5T_NATIVE_DOUBLE, {b.solid->density});
    numeric_attribute<double>(g, "volume", H5T_NATIVE_DOUBLE, {b.solid->volume});
    if (b.solid->kind == Solid::Kind::Ellipsoid) {
      numeric_attribute<double>(g, "semi_axes", H5T_NATIVE_DOUBLE,
                                {b.solid->semi_axes.x(), b.solid->semi_axes.y(), b.solid->semi_axes.z()});
    } else {  // the mesh in the body frame, so that the file alone can draw the body
      write_mesh(g, b.solid->mesh, scene.units);
    }
    numeric_attribute<double>(g, "offset", H5T_NATIVE_DOUBLE,
                              {b.solid->offset.x(), b.solid->offset.y(), b.solid->offset.z()});
    std::vector<double> rotation;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) rotation.push_back(b.solid->rotation(r, c));
    numeric_attribute<double>(g, "rotation", H5T_NATIVE_DOUBLE, rotation);  // row-major
    numeric_attribute<double>(g, "stretch", H5T_NATIVE_DOUBLE,
                              {b.solid->stretch.x(), b.solid->stretch.y(), b.solid->stretch.z()});
  }

  // Bodies given by their gravity field: where the coefficients came from and what they are.
  io::H5Handle fields;
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const Body& b = sys.body(i);
    if (!b.field) continue;
    if (!fields.valid()) fields = io::H5Handle(make_group(parameters, "fields"));
    const io::H5Handle g(make_group(fields, b.name.c_str()));
    string_attribute(g, "stokes", scene.root.at("bodies").items()[i].at("gravity").at("stokes").as_string());
    numeric_attribute<int>(g, "degree", H5T_NATIVE_INT, {b.field->degree});
    numeric_attribute<double>(g, "reference_radius", H5T_NATIVE_DOUBLE, {b.field->reference_radius});
    numeric_attribute<double>(g, "GM", H5T_NATIVE_DOUBLE, {sys.G() * b.mass});
    string_attribute(g, "normalization", b.field->normalized ? "fully normalized" : "unnormalized");
  }

  const io::H5Handle particles(make_group(m.file, "particles"));
  const io::H5Handle bodies(make_group(particles, "bodies"));
  std::vector<std::string> names;
  std::vector<double> masses;
  for (const auto& b : sys.bodies()) {
    names.push_back(b.name);
    masses.push_back(b.mass);
  }
  string_list_dataset(bodies, "name", names);
  double_dataset(bodies, "mass", masses);
  {
    const io::H5Handle mass(check_id(H5Dopen2(bodies, "mass", H5P_DEFAULT), "mass"));
    string_attribute(mass, "unit", scene.units.of_mass());
    string_attribute(mass, "description", "mass of each body");
    const io::H5Handle name(check_id(H5Dopen2(bodies, "name", H5P_DEFAULT), "name"));
    string_attribute(name, "description", "the bodies' names, in the order of every [body] axis");
  }
  if (m.n_rigid > 0) {  // J_k, principal-axes body frame, [rigid body][3][3]
    std::vector<double> inertia;
    std::vector<int> rigid_index;
    for (std::size_t k = 0; k < sys.rigid_count(); ++k) {
      const Body& b = sys.body(sys.body_of_rigid(k));
      rigid_index.push_back(static_cast<int>(sys.body_of_rigid(k)));
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) inertia.push_back(b.inertia(r, c));
    }
    const hsize_t dims[3] = {m.n_rigid, 3, 3};
    const io::H5Handle space(H5Screate_simple(3, dims, nullptr));
    const io::H5Handle d(check_id(H5Dcreate2(bodies, "inertia", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT,
                                             H5P_DEFAULT), "inertia"));
    check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, inertia.data()), "inertia");
    numeric_attribute<int>(d, "body_index", H5T_NATIVE_INT, rigid_index);
    string_attribute(d, "description", "inertia tensor J of each rigid body in its body frame");
    string_attribute(d, "unit", scene.units.of_inertia());
  }
  create_series(scene);
  if (m.layout.stm_columns > 0 || m.layout.sensitivity_columns > 0) {  // what the rows and columns are
    const io::H5Handle derivatives(check_id(H5Gopen2(m.file, "derivatives", H5P_DEFAULT), "derivatives"));
    string_list_dataset(derivatives, "coordinates", State::tangent_coordinates(sys));
    const io::H5Handle names(check_id(H5Dopen2(derivatives, "coordinates", H5P_DEFAULT), "coordinates"));
    string_attribute(names, "description",
                     "the coordinates of z = (x, θ, γ, Π) (docs/equations.md eq. 21.1) in the order of the rows "
                     "of /derivatives/stm and /derivatives/sensitivity, and of the columns of /derivatives/stm "
                     "(the same coordinates at t0)");
    if (m.layout.sensitivity_columns > 0) {
      string_list_dataset(derivatives, "parameters", options.sensitivity_names);
      const io::H5Handle keys(check_id(H5Dopen2(derivatives, "parameters", H5P_DEFAULT), "parameters"));
      string_attribute(keys, "description",
                       "the keys (run.sensitivities, as --set takes them) of the columns of /derivatives/sensitivity");
    }
  }
  // The commit counter: frames [0, frames_complete) are complete; a killed run's series keep
  // their allocated length, with fill (NaN, step −1) or an unfinished block after it.
  {
    const io::H5Handle space(H5Screate(H5S_SCALAR)), plist(H5Pcreate(H5P_DATASET_CREATE));
    H5Pset_layout(plist, H5D_CONTIGUOUS);
    H5Pset_alloc_time(plist, H5D_ALLOC_TIME_EARLY);
    m.complete = check_id(H5Dcreate2(m.file, "frames_complete", H5T_NATIVE_INT64, space, H5P_DEFAULT,
                                     plist, H5P_DEFAULT), "frames_complete");
    string_attribute(m.complete, "description",
                     "the number of complete frames: every series holds exactly this many after a "
                     "run that ended; after a killed run, read series[:frames_complete]");
    m.write_complete(0);
  }
  m.flush_file("flushing the output file");
}

// Every series of the frame schema (io/frame_schema.hpp) the scene has, each in its group
// (created on the way: H5MD elements get hard links to position's step and time), then
// /checkpoint/checksum over the checkpointed ones.
void H5Writer::create_series(const Scene& scene) {
  Impl& m = *impl_;
  const System& sys = scene.system;
  std::vector<int> rigid_index;
  for (std::size_t k = 0; k < sys.rigid_count(); ++k) rigid_index.push_back(static_cast<int>(sys.body_of_rigid(k)));
  {
    const io::H5Handle checkpoint(make_group(m.file, "checkpoint"));
    string_attribute(checkpoint, "description",
                     "the exact state and the work at every frame, from which `noether run --resume` "
                     "continues a run");
    if (!m.options.resumed.empty()) string_attribute(checkpoint, "resumed", m.options.resumed);
    if (!std::isnan(m.options.t_origin)) {  // checksummed: a continuation's step grid starts there
      scalar_attribute(checkpoint, "t_origin", m.options.t_origin);
      numeric_attribute<std::uint64_t>(checkpoint, "t_origin_checksum", H5T_NATIVE_UINT64,
                                       {io::checksum64(&m.options.t_origin, sizeof(double))});
    }
  }
  const auto schema = io::frame_schema();
  const auto checkpointed = io::checkpointed_series();
  m.columns.reserve(schema.size());
  m.checkpointed.assign(checkpointed.size(), nullptr);
  std::string step_group;  // the H5MD element holding step and time (position's)
  const std::int64_t integer_fill = -1;
  const double real_fill = std::numeric_limits<double>::quiet_NaN();
  for (const auto& q : schema) {
    if (!io::present(q, m.layout)) continue;
    const std::string path = q.path, parent = path.substr(0, path.rfind('/')), name = path.substr(path.rfind('/') + 1);
    bool created = false;
    const io::H5Handle group(group_at(m.file, parent, &created));
    if (q.element == io::Element::kH5md && created) {
      if (step_group.empty()) {
        step_group = parent;
      } else {  // {step, time} of every element are hard links to position's
        for (const char* link : {"step", "time"})
          check(H5Lcreate_hard(m.file, (step_group + "/" + link).c_str(), group, link, H5P_DEFAULT, H5P_DEFAULT),
                "linking step and time");
      }
      if (io::rigid_only(q))
        numeric_attribute<int>(group, "body_index", H5T_NATIVE_INT, rigid_index);
      if (const auto pair = binary_pair(sys); pair && io::binary_only(q)) {  // the binary's series
        string_attribute(group, "primary", sys.body(pair->primary).name);
        string_attribute(group, "secondary", sys.body(pair->secondary).name);
      }
    }
    std::vector<hsize_t> shape;
    for (auto d : io::frame_shape(q, m.layout)) shape.push_back(d);
    const bool integer = io::is_integer(q);
    auto series = std::make_unique<Series>(group, name.c_str(), integer ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE,
                                           shape, m.allocated,
                                           integer ? static_cast<const void*>(&integer_fill) : &real_fill);
    series->reserve_frames(std::min<hsize_t>(m.options.block_frames, m.allocated));
    string_attribute(series->dataset, "unit", io::unit_of(q.unit, scene.units));
    string_attribute(series->dataset, "description", q.description);
    if (q.extent == io::Extent::kRunFeatures) {  // the name of each field, one a line
      std::string fields;
      for (const auto& f : m.options.feature_fields) fields += (fields.empty() ? "" : "\n") + f;
      string_attribute(series->dataset, "fields", fields);
    }
    std::ptrdiff_t feature_offset = -1;  // where its numbers are among the features' (write_frame)
    if (q.fill.by_feature) {
      feature_offset = 0;
      for (const auto& declared : m.options.feature_series) {
        if (declared.name == q.name) break;
        feature_offset += static_cast<std::ptrdiff_t>(declared.size());
      }
    }
    m.columns.push_back({&q, std::move(series), feature_offset});
    if (q.checksum_column >= 0) m.checkpointed[static_cast<std::size_t>(q.checksum_column)] = &m.columns.back();
  }
  const io::H5Handle checkpoint(H5Gopen2(m.file, "checkpoint", H5P_DEFAULT));
  const std::uint64_t zero = 0;
  m.checksum_series = std::make_unique<Series>(checkpoint, "checksum", H5T_NATIVE_UINT64,
                                               std::vector<hsize_t>{checkpointed.size()}, m.allocated, &zero);
  m.checksum_series->reserve_frames(std::min<hsize_t>(m.options.block_frames, m.allocated));
  string_attribute(m.checksum_series->dataset, "description",
                   "checksum64 of each frame of the series named in `columns`, seeded with the frame's index "
                   "(0: the series is absent); `noether run --resume` verifies every frame it reads");
  std::string columns;
  for (const auto* q : checkpointed) {
    if (!columns.empty()) columns += '\n';
    columns += q->path;
  }
  string_attribute(m.checksum_series->dataset, "columns", columns);
}

void H5Writer::write_pair_models(const std::vector<PairModel>& models) {
  if (models.empty()) return;
  Impl& m = *impl_;
  settle();
  const io::H5Handle parameters(check_id(H5Gopen2(m.file, "parameters", H5P_DEFAULT), "/parameters"));
  if (H5Lexists(parameters, "pair_models", H5P_DEFAULT) > 0) H5Ldelete(parameters, "pair_models", H5P_DEFAULT);
  const io::H5Handle group(make_group(parameters, "pair_models"));
  for (const auto& p : models) {
    const io::H5Handle g(make_group(group, (p.body_a + "–" + p.body_b).c_str()));
    string_attribute(g, "body_a", p.body_a);
    string_attribute(g, "body_b", p.body_b);
    string_attribute(g, "model", p.model);
    numeric_attribute<int>(g, "order", H5T_NATIVE_INT, {p.order});
    numeric_attribute<double>(g, "tolerance", H5T_NATIVE_DOUBLE, {p.tolerance});
    numeric_attribute<double>(g, "estimated_error", H5T_NATIVE_DOUBLE, {p.estimated_error});
    numeric_attribute<double>(g, "separation", H5T_NATIVE_DOUBLE, {p.separation});
    numeric_attribute<int>(g, "exceeded", H5T_NATIVE_INT, {p.exceeded ? 1 : 0});
    if (p.exceeded) {
      numeric_attribute<double>(g, "exceeded_time", H5T_NATIVE_DOUBLE, {p.exceeded_time});
      numeric_attribute<double>(g, "exceeded_separation", H5T_NATIVE_DOUBLE, {p.exceeded_separation});
      numeric_attribute<double>(g, "exceeded_error", H5T_NATIVE_DOUBLE, {p.exceeded_error});
    }
  }
  m.flush_file("flushing the output file");
}

namespace {

// A [rows][columns] dataset of `type` from row-major values, with its description and unit.
template <class T>
void table_dataset(hid_t parent, const char* name, hid_t type, const std::vector<T>& values, hsize_t columns,
                   const std::string& description, const std::string& unit) {
  const hsize_t dims[2] = {columns ? values.size() / columns : 0, columns};
  const io::H5Handle space(H5Screate_simple(columns > 1 ? 2 : 1, dims, nullptr));
  const io::H5Handle d(check_id(H5Dcreate2(parent, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), name));
  if (!values.empty()) check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), name);
  string_attribute(d, "description", description);
  if (!unit.empty()) string_attribute(d, "unit", unit);
}

}  // namespace

// /test_particles: each particle's start, end and fate (docs/user-guide.md, "Particles").
void H5Writer::write_particles(const ParticleSwarm& swarm, const Scene& scene) {
  Impl& m = *impl_;
  settle();
  if (H5Lexists(m.file, "test_particles", H5P_DEFAULT) > 0) H5Ldelete(m.file, "test_particles", H5P_DEFAULT);
  const io::H5Handle group(make_group(m.file, "test_particles"));
  const std::size_t n = swarm.size();
  std::vector<double> x0, v0, x, v, t, point, velocity;
  std::vector<int> fate, body;
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    const ParticleOutcome& o = swarm.outcomes()[i];
    for (int k = 0; k < 3; ++k) {
      x0.push_back(swarm.initial_positions()[i][k]);
      v0.push_back(swarm.initial_velocities()[i][k]);
      x.push_back(swarm.positions()(k, c));
      v.push_back(swarm.velocities()(k, c));
      point.push_back(o.point[k]);
      velocity.push_back(o.velocity[k]);
    }
    t.push_back(o.t);
    fate.push_back(static_cast<int>(o.fate));
    body.push_back(o.body);
  }
  const Units& u = scene.units;
  table_dataset(group, "initial_position", H5T_NATIVE_DOUBLE, x0, 3, "each particle's position at t0, inertial", u.of_length());
  table_dataset(group, "initial_velocity", H5T_NATIVE_DOUBLE, v0, 3, "each particle's velocity at t0, inertial", u.of_velocity());
  table_dataset(group, "position", H5T_NATIVE_DOUBLE, x, 3,
                "each particle's position where the run ended, or where it landed or escaped", u.of_length());
  table_dataset(group, "velocity", H5T_NATIVE_DOUBLE, v, 3,
                "each particle's velocity where the run ended, or when it landed or escaped (inertial)", u.of_velocity());
  table_dataset(group, "fate", H5T_NATIVE_INT, fate, 1, "0: in flight at the end, 1: landed on a body, 2: escaped", "");
  table_dataset(group, "time", H5T_NATIVE_DOUBLE, t, 1, "the time of the landing or escape (NaN: in flight)", u.of_time());
  table_dataset(group, "body", H5T_NATIVE_INT, body, 1,
                "what it landed on, by its index in 'surfaces' (-1: none): the bodies as in /particles/bodies/name, "
                "then the point masses that pull the particles (a prescribed body with a radius)", "");
  table_dataset(group, "impact_point", H5T_NATIVE_DOUBLE, point, 3,
                "where it landed, in the body's frame (centre of mass, principal axes); on a prescribed body, from its "
                "centre in inertial axes", u.of_length());
  table_dataset(group, "impact_velocity", H5T_NATIVE_DOUBLE, velocity, 3,
                "its velocity relative to the spinning surface where it landed, body frame (on a prescribed body: "
                "relative to its centre, inertial)", u.of_velocity());
  string_list_dataset(group, "fields", swarm.fields());
  string_list_dataset(group, "surfaces", swarm.surfaces());
  std::vector<std::string> names;
  for (const Body& b : scene.system.bodies()) names.push_back(b.name);
  string_attribute(group, "description",
                   "massless particles (the scene's particles:), each body's field as they felt it in 'fields' (its first " +
                       std::to_string(names.size()) + " entries, one per body; then what each force beyond the potential "
                       "was to them)");
  numeric_attribute<std::int64_t>(group, "verlet_steps", H5T_NATIVE_INT64, {swarm.particle_steps()});
  m.flush_file("flushing the output file");
}

}  // namespace noether
