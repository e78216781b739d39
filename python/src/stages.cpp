// The pipeline's stages in-process (slice-joints, slice-cut, slice-prune, slice-vertices) and
// the files: each stage makes a new Model; the library runs off the interpreter's lock
// (run_interruptible).
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rockslice.hpp"
#include "slice/cut.hpp"
#include "slice/error.hpp"
#include "slice/hash.hpp"
#include "slice/scene.hpp"
#include "slice/stability.hpp"
#include "slice/threads.hpp"
#include "slice/vertices.hpp"

namespace rockslice {
namespace {

namespace fs = std::filesystem;

std::shared_ptr<Model> make_model(slice::BlockSystem&& bs, Stage stage,
                                  const slice::Provenance& prov) {
  auto m = std::make_shared<Model>();
  m->bs = std::make_shared<slice::BlockSystem>(std::move(bs));
  m->stage = stage;
  m->provenance = prov;
  return m;
}

Stage stage_of(const slice::BlockSystem& bs) {
  return bs.geometry ? Stage::geometry : bs.pruned ? Stage::pruned : Stage::blocks;
}

// The joints of a scene: a file (`text` empty) or TOML text standing for the file `name`.
// `prov`: who made them from what, as slice-joints records it: the scene (the file's bytes or
// the text's) and every file it names (mesh zones, surfaces, DFN files), hashed.
slice::JointSystem generate(const std::string& text, const fs::path& name,
                            std::optional<std::uint64_t> seed, const std::string& call,
                            slice::Provenance& prov) {
  slice::Scene scene = text.empty() ? slice::load_scene(name) : slice::parse_scene(text, name);
  if (seed) scene.seed = *seed;
  prov = python_provenance(call, name.string(),
                           text.empty() ? slice::sha256_file(name) : slice::sha256_hex(text));
  for (const auto& [what, file] : slice::scene_files(scene)) slice::add_input(prov, file);
  return slice::generate_joints(scene);
}

// An input file that does not exist is an OSError (FileNotFoundError), with the library's line.
void check_input(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    const std::string line =
        slice::Error(path.string(), "no such file",
                     "check the path (relative to " + fs::current_path(ec).string() + ")")
            .what();
    raise(PyExc_FileNotFoundError, line);
  }
}

// Refuses a save over one of the model's inputs, as the tools refuse an output on their input:
// model.save('s.toml') would turn the scene (or a DFN file it names) into HDF5. The inputs are
// the provenance's (the scene, then each file it names, "; " between), for a model made in this
// process from a scene; a loaded model's were named by another run, from its own directory.
void check_not_an_input(const Model& model, const fs::path& path) {
  const slice::Provenance& prov = model.provenance;
  if (prov.tool != python_provenance("", "", "").tool) return;
  const auto split = [](const std::string& s) {
    std::vector<std::string> parts;
    for (std::size_t start = 0;;) {
      const std::size_t end = s.find("; ", start);
      parts.push_back(s.substr(start, end - start));
      if (end == std::string::npos) return parts;
      start = end + 2;
    }
  };
  const std::vector<std::string> inputs = split(prov.input);
  const std::vector<std::string> sha = split(prov.input_sha256);
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    std::error_code ec;
    if (inputs[i].empty() || !fs::equivalent(inputs[i], path, ec)) continue;
    // A dict scene stands under a name ("scene") that no file need have: a file of that name
    // is its input only if it holds the dict's text.
    if (i == 0 && inputs[i] == "scene" && i < sha.size() && sha[i] != slice::sha256_file(path))
      continue;
    throw slice::Error(path.string(),
                       "the path and the model's input (" + inputs[i] +
                           ") are the same file: the output would overwrite the input",
                       "give save() a different path; nothing was written");
  }
}

struct CutArgs {
  std::string lp = "native";
  int threads = 0;
  std::int64_t max_blocks = 0;
  bool certify = false;
};

slice::CutOptions cut_options(const CutArgs& a) {
  if (a.threads < 0)
    throw slice::Error("threads", "is " + std::to_string(a.threads),
                       "give 0 (all cores) or a positive number");
  if (a.max_blocks < 0)
    throw slice::Error("max_blocks", "is " + std::to_string(a.max_blocks),
                       "give 0 (the scene's [options] max_blocks) or a positive number");
  slice::CutOptions opt;
  opt.backend = slice::parse_lp_backend(a.lp);
  opt.threads = a.threads;
  opt.max_blocks = a.max_blocks;
  opt.certify = a.certify;
  return opt;
}

}  // namespace

void bind_stages(py::module_& m) {
  m.def(
      "_joints",
      [](const std::string& text, const fs::path& name, std::optional<std::uint64_t> seed,
         const std::string& call, const py::object& progress) {
        if (text.empty()) check_input(name);
        slice::BlockSystem bs;
        slice::Provenance prov;
        run_interruptible(
            [&](const slice::Progress&) { bs.joints = generate(text, name, seed, call, prov); },
            progress);
        return make_model(std::move(bs), Stage::joints, prov);
      },
      py::arg("text"), py::arg("name"), py::arg("seed"), py::arg("call"), py::arg("progress"));

  m.def(
      "_slice",
      [](const std::string& text, const fs::path& name, std::optional<std::uint64_t> seed,
         const CutArgs& args, bool prune, const std::string& call, const py::object& progress) {
        if (text.empty()) check_input(name);
        const slice::CutOptions opt = cut_options(args);
        slice::BlockSystem bs;
        slice::Provenance prov;
        run_interruptible(
            [&](const slice::Progress& p) {
              const slice::JointSystem js = generate(text, name, seed, call, prov);
              bs = std::move(slice::cut_blocks(js, opt, p).blocks);
              if (!prune) return;
              // As slice-cut --prune: the cut's blocks are solids by construction.
              slice::prune_blocks(bs, opt.backend, p, opt.certify, opt.threads, false);
              slice::compute_geometry(bs, p, opt.threads);
            },
            progress);
        const Stage stage = stage_of(bs);
        return make_model(std::move(bs), stage, prov);
      },
      py::arg("text"), py::arg("name"), py::arg("seed"), py::arg("cut"), py::arg("prune"),
      py::arg("call"), py::arg("progress"));

  py::class_<CutArgs>(m, "_CutArgs")
      .def(py::init<>())
      .def_readwrite("lp", &CutArgs::lp)
      .def_readwrite("threads", &CutArgs::threads)
      .def_readwrite("max_blocks", &CutArgs::max_blocks)
      .def_readwrite("certify", &CutArgs::certify);

  // The stages after the joints: `work` makes the new model's blocks, from a copy of the
  // model's (the model stays as it was) or, for the cut, from nothing.
  using Work = std::function<void(slice::BlockSystem&, const slice::CutOptions&, const Model&,
                                  const slice::Progress&)>;
  const auto def_stage = [&m](const char* name, Stage made, Work work) {
    m.def(
        name,
        [made, work](const Model& model, const CutArgs& args, const std::string& call,
                     const py::object& progress) {
          const slice::CutOptions opt = cut_options(args);
          slice::BlockSystem bs;
          if (made != Stage::blocks) {
            if (model.stage == Stage::joints)
              throw slice::Error("model", "has no blocks (a joints.h5)",
                                 "cut it first: rockslice.cut(model)");
            bs = *model.bs;
          }
          run_interruptible([&](const slice::Progress& p) { work(bs, opt, model, p); }, progress);
          slice::Provenance prov = model.provenance;
          prov.command_line = call;
          return make_model(std::move(bs), made, prov);
        },
        py::arg("model"), py::arg("cut"), py::arg("call"), py::arg("progress"));
  };
  def_stage("_cut", Stage::blocks, [](auto& bs, const auto& opt, const auto& model, const auto& p) {
    bs = std::move(slice::cut_blocks(model.bs->joints, opt, p).blocks);
  });
  def_stage("_prune", Stage::pruned, [](auto& bs, const auto& opt, const auto&, const auto& p) {
    slice::prune_blocks(bs, opt.backend, p, opt.certify, opt.threads);
  });
  def_stage("_vertices", Stage::geometry,
            [](auto& bs, const auto& opt, const auto&, const auto& p) {
              // As slice-vertices --prune: blocks not yet pruned are pruned first.
              if (!bs.pruned) slice::prune_blocks(bs, opt.backend, p, opt.certify, opt.threads);
              slice::compute_geometry(bs, p, opt.threads);
            });

  // slice-stability in-process: the model with /contacts and /stability.
  m.def(
      "_stability",
      [](const Model& model, const std::string& free_faces, double density, double seismic,
         double seismic_azimuth, std::optional<double> water_table, double support_pressure,
         double fos_target, std::int64_t max_group, int threads, const std::string& call,
         const py::object& progress) {
        if (model.stage != Stage::geometry)
          throw slice::Error("model", std::string("is of stage '") + to_string(model.stage) + "'",
                             "compute its vertices first: rockslice.vertices(model)");
        slice::StabilityOptions opt;
        if (!free_faces.empty()) opt.free_faces = slice::parse_free_faces(free_faces);
        opt.density = density;
        opt.seismic = seismic;
        opt.seismic_azimuth_deg = seismic_azimuth;
        opt.water_table = water_table;
        opt.support_pressure = support_pressure;
        opt.fos_target = fos_target;
        opt.max_group = max_group < 1 ? 0 : std::size_t(max_group);  // 0: refused below
        slice::check_stability_options(opt);
        slice::BlockSystem bs = *model.bs;
        run_interruptible(
            [&](const slice::Progress&) {
              slice::with_threads(threads,
                                  [&] { bs.stability = slice::analyse_stability(bs, opt); });
            },
            progress);
        slice::Provenance prov = model.provenance;
        prov.command_line = call;
        return make_model(std::move(bs), Stage::geometry, prov);
      },
      py::arg("model"), py::arg("free_faces"), py::arg("density"), py::arg("seismic"),
      py::arg("seismic_azimuth"), py::arg("water_table"), py::arg("support_pressure"),
      py::arg("fos_target"), py::arg("max_group"), py::arg("threads"), py::arg("call"),
      py::arg("progress"));

  m.def(
      "_with_joints",
      [](const Model& model, const std::vector<std::int64_t>& index) {
        if (model.stage != Stage::joints)
          throw slice::Error("model", std::string("is of stage '") + to_string(model.stage) + "'",
                             "choose joints before the cut: on rockslice.joints(scene) or a "
                             "joints.h5");
        slice::BlockSystem bs;
        bs.joints = model.bs->joints;
        const auto& all = model.bs->joints.joints;
        bs.joints.joints.clear();
        for (const std::int64_t i : index) {
          if (i < 0 || std::size_t(i) >= all.size())
            throw slice::Error("index", "joint " + std::to_string(i) + " does not exist",
                               "give joints from 0 to " + std::to_string(all.size() - 1));
          bs.joints.joints.push_back(all[std::size_t(i)]);
        }
        return make_model(std::move(bs), Stage::joints, model.provenance);
      },
      py::arg("model"), py::arg("index"));

  m.def(
      "load",
      [](const fs::path& path) {
        check_input(path);
        slice::BlockSystem bs;
        slice::FileHeader header;
        {
          py::gil_scoped_release unlocked;
          header = slice::read_header(path);
          if (header.kind == slice::FileKind::joints)
            bs.joints = slice::read_joints(path);
          else
            bs = slice::read_blocks(path);
        }
        const Stage stage = header.kind == slice::FileKind::joints ? Stage::joints : stage_of(bs);
        return make_model(std::move(bs), stage, header.provenance);
      },
      py::arg("path"),
      R"(The model in a joints.h5, blocks.h5 or geom.h5 file (a joints.h5 gives a model of stage
'joints', without blocks). Raises FileNotFoundError for a missing file and rockslice.Error
(a ValueError) with the tools' one-line message for a bad one.)");

  m.def(
      "_save",
      [](const Model& model, const fs::path& path, bool compress, const py::dict& given) {
        const slice::WriteOptions opt{compress};
        // The provenance recorded, the model's unless the caller gives some of its fields.
        slice::Provenance prov = model.provenance;
        const std::pair<const char*, std::string*> fields[] = {
            {"tool", &prov.tool},
            {"version", &prov.version},
            {"command_line", &prov.command_line},
            {"input", &prov.input},
            {"input_sha256", &prov.input_sha256}};
        for (const auto& [name, field] : fields)
          if (given.contains(name))
            *field = text_arg(given[name], std::string("provenance['") + name + "']");
        check_not_an_input(model, path);  // the model's, not `given`: what was read
        try {
          py::gil_scoped_release unlocked;
          if (model.stage == Stage::joints)
            slice::write_joints(path, model.bs->joints, prov, opt);
          else
            slice::write_blocks(path, *model.bs, prov, opt);
        } catch (const slice::Error& e) {
          // The file could not be written: an OSError, with the library's line.
          raise(PyExc_OSError, e.what());
        }
      },
      py::arg("model"), py::arg("path"), py::arg("compress"), py::arg("provenance"));
}

}  // namespace rockslice
