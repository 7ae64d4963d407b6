#include "pipeline/run_resume.h"

#include <fmt/format.h>

#include <chrono>
#include <fstream>

#include "common/atomic_file.h"
#include "common/input_file.h"
#include "io/json_file.h"
#include "io/pvti.h"
#include "io/run_folder.h"
#include "io/run_report.h"
#include "schema/report_schema.h"
#include "measure/measures.h"
#include "model/run_options.h"

namespace cmcsurf {

namespace {

namespace fs = std::filesystem;

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

CheckpointSink::CheckpointSink(fs::path dir, const RunParams& params, nlohmann::json outputs,
                               double every, std::shared_ptr<const Decomposition> world,
                               std::function<bool()> stop_requested,
                               std::function<void(const std::string&)> warn)
    : dir_(std::move(dir)),
      params_(params_json(params)),
      outputs_(std::move(outputs)),
      every_(every),
      world_(std::move(world)),
      stop_requested_(std::move(stop_requested)),
      warn_(std::move(warn)),
      last_(now_seconds()) {}

void CheckpointSink::attach(RunContext& context) {
  context.control = [this] {
    const bool stop = stop_requested_ && stop_requested_();
    int code = stop ? 2 : (every_ > 0.0 && now_seconds() - last_ >= every_ ? 1 : 0);
    if (world_ && world_->distributed()) code = int(world_->max(double(code)));  // one decision
    return code == 2 ? RunControl::kStop : code == 1 ? RunControl::kCheckpoint
                                                     : RunControl::kContinue;
  };
  context.checkpoint = [this](const Checkpoint& c) {
    try {
      write(c);
    } catch (const std::exception& e) {
      if (!warned_ && warn_)
        warn_(fmt::format("no checkpoint written ({}); the run goes on", e.what()));
      warned_ = true;
    }
    last_ = now_seconds();
  };
}

void CheckpointSink::retarget(fs::path dir, const RunParams& params) {
  dir_ = std::move(dir);
  params_ = params_json(params);
}

void CheckpointSink::write(const Checkpoint& c) {
  const double t0 = now_seconds();
  if (world_ && world_->distributed() && !c.result.phi.decomposition()) {
    // Fields every process holds whole (a grid the run does not split): rank 0 writes them.
    if (world_->rank() == 0) write_checkpoint(dir_ / kCheckpointFileName, params_, c, outputs_);
  } else {
    // Whole grids: one file (format 6); blocks: every process writes its own piece (format 7,
    // collective), so that no process holds the whole grid (io/checkpoint.h).
    write_checkpoint(dir_ / kCheckpointFileName, params_, c, outputs_);
  }
  ++written_;
  seconds_ += now_seconds() - t0;
}

InterruptedRun write_interrupted_run(const fs::path& dir, const RunParams& params,
                                     RunInterrupted& stop, CheckpointSink& sink, int threads,
                                     const std::string& resume_command,
                                     const std::string& signal, const nlohmann::json& extra) {
  Checkpoint& c = stop.checkpoint;
  InterruptedRun out;
  out.root = !c.result.phi.decomposition() || c.result.phi.decomposition()->rank() == 0;
  try {
    sink.write(c);
  } catch (const std::exception& e) {
    out.failure = e.what();
  }
  // The report of the field so far (on the stage's grid, which is coarser than --grid while
  // a continuation works on a coarse level).
  RunResult& r = c.result;
  r.final = measure_field(r.phi, params.epsilon);
  r.stop_reason = "interrupted";
  r.converged = false;
  if (out.root) {
    nlohmann::json report = run_report(params, r, threads);
    report["stop_reason"] = "interrupted";
    report["checkpoint"] = {{"file", out.failure.empty() ? kCheckpointFileName : ""},
                            {"step", c.step},
                            {"stage", run_stage_name(c.cursor.stage)},
                            {"grid", c.cursor.grid},
                            {"signal", signal},
                            {"anderson_columns", c.anderson ? c.anderson->columns : 0}};
    report["checkpoints_written"] = sink.written();
    report["checkpoint_seconds"] = sink.seconds();
    report["resume"] = resume_command;
    for (const auto& [key, value] : extra.items()) report[key] = value;
    write_history_csv(dir / "history.csv", r.history);
    write_json_atomic(dir / "report.json", report);
  }
  return out;
}

LoadedCheckpoint load_checkpoint(const fs::path& dir, RunEntry entry,
                                 const std::shared_ptr<const Decomposition>& world) {
  const fs::path file = dir / kCheckpointFileName;
  // Under a decomposition every process reads only its blocks (of the file, or of the pieces
  // that hold them), so the processes may see different errors: they agree on the first.
  const bool split = world && world->distributed();
  CheckpointReadOptions options;
  if (split) options.decomposition = world;
  CheckpointFile f;
  std::string error;
  try {
    f = read_checkpoint(file, options);
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  if (split) error = world->first_error(error);
  if (!error.empty()) throw OptionError(fmt::format("--resume: {}", error));
  // The run of these parameters must pass through the checkpoint's grid and stage, on this
  // many processes (the fields are empty where that grid does not split).
  const std::string problem = resume_problem(f.checkpoint, params_from_json(f.params), entry,
                                             split ? world.get() : nullptr);
  if (!problem.empty())
    throw OptionError(fmt::format(
        "--resume: {}: a run with its parameters cannot continue it{}: {}", file.string(),
        split ? fmt::format(" on {} processes", world->ranks()) : "", problem));
  LoadedCheckpoint loaded{std::move(f.params), std::move(f.outputs), nullptr};
  auto c = std::make_shared<Checkpoint>(std::move(f.checkpoint));
  if (split) {  // the blocks were read interior only
    for (Field* x : {&c->result.phi, &c->stepper.nu, &c->stepper.prev_phi, &c->stepper.prev_nu})
      if (x->n() != 0) x->exchange_halo();
  }
  loaded.checkpoint = std::move(c);
  return loaded;
}

RunParams resumed_run_params(const RunParams& given, const nlohmann::json& saved,
                             const fs::path& file,
                             const std::function<bool(const RunOption&)>& given_option,
                             const std::function<std::string(const RunOption&)>& shown) {
  RunParams p;
  try {
    p = params_from_json(saved);
  } catch (const std::exception& e) {
    throw OptionError(fmt::format("--resume: {}: {}", file.string(), e.what()));
  }
  const RunOption* o = changed_run_option(given, p, given_option);
  if (o != nullptr) {
    const nlohmann::json mine = params_json(given), theirs = params_json(p);
    throw OptionError(fmt::format(
        "{} {}: {} was written by a run with {} {}; a resumed run keeps the parameters it "
        "started with (leave the option out, or start a new run with another --out)",
        shown(*o), mine[o->key].dump(), file.string(), o->key, theirs[o->key].dump()));
  }
  return p;
}

SweepJson resumed_sweep(
    const fs::path& dir, const SweepParams& given, const SweepResumeNames& names,
    const std::function<RunParams(const nlohmann::json&, const fs::path&)>& run_params) {
  const fs::path file = dir / "sweep.json";
  nlohmann::json j;
  SweepJson saved;  // checked: ranges, member names; no executables among its outputs
  try {
    j = read_json_file(file);
    saved = parse_sweep_json(j);
    j.at("parameters");
  } catch (const std::invalid_argument& e) {
    throw OptionError(fmt::format("{}: {}: {}", names.resume, file.string(), e.what()));
  } catch (const std::exception& e) {
    throw OptionError(
        fmt::format("{} {}: no sweep to resume ({})", names.resume, dir.string(), e.what()));
  }
  saved.sweep.run = run_params(j.at("parameters"), file);
  try {
    check_sweep_params(saved.sweep);
  } catch (const std::invalid_argument& e) {
    throw OptionError(fmt::format("{}: {}: {}", names.resume, file.string(), e.what()));
  }
  if (j.contains("outputs") && !j["outputs"].is_object())
    throw OptionError(
        fmt::format("{}: {}: 'outputs' is not an object", names.resume, file.string()));
  auto differs = [&](const std::string& option, bool given_here, bool d) {
    if (d && given_here)
      throw OptionError(fmt::format("{}: differs from the sweep in {} ({}); a resumed sweep "
                                    "keeps its members (leave the option out)",
                                    option, file.string(), option));
  };
  const SweepParams& sp = saved.sweep;
  differs(names.surfaces, names.surfaces_given, given.surfaces != sp.surfaces);
  differs(names.fractions, names.fractions_given, given.fractions != sp.fractions);
  differs(names.continuation, names.continuation_given, given.continuation != sp.continuation);
  return saved;
}

MemberDecision decide_member(const fs::path& mdir, const SweepMember& m, bool resuming,
                             bool force, FolderClaim& claim, int* removed) {
  MemberDecision d;
  try {
    // One writer per member folder too (a second sweep, a run pointed into it).
    claim = claim_output_folder(mdir, {.kind = "run", .option = "member folder", .force = force});
    const int n = remove_stale_temporaries(mdir);  // of an earlier process killed mid-write
    if (removed) *removed = n;
    if (resuming && fs::exists(mdir / kCheckpointFileName)) {
      d.kind = MemberDecision::Kind::kResume;
    } else if (resuming && fs::exists(mdir / "report.json")) {
      nlohmann::json report = read_json_file(mdir / "report.json");
      if (report.value("stop_reason", "") != "interrupted" &&
          (fs::exists(mdir / kRunFieldVti) || fs::exists(mdir / kRunFieldPvti)) &&
          report.value("parameters", nlohmann::json()) == params_json(m.params) &&
          report.value("started_from", "") == m.started_from) {
        d.kind = MemberDecision::Kind::kSkip;
        d.report = std::move(report);
      }
    }
    if (d.kind == MemberDecision::Kind::kRun) {
      clear_run_outputs(mdir);
      remove_checkpoint(mdir / kCheckpointFileName);
    }
  } catch (const std::exception& e) {
    d.kind = MemberDecision::Kind::kFailed;
    d.failure = e.what();
  }
  return d;
}

MemberDecision::Kind agree_member_decision(const Decomposition& group, MemberDecision& d) {
  using K = MemberDecision::Kind;
  // The kinds travel as their index in this list, which names every one of them.
  constexpr K kKinds[] = {K::kRun, K::kResume, K::kSkip, K::kFailed};
  double index = 0.0;
  for (int i = 0; i < 4; ++i)
    if (kKinds[i] == d.kind) index = i;
  group.broadcast(&index, 1);
  d.kind = kKinds[int(index)];
  d.failure = group.first_error(d.failure);
  return d.kind;
}

}  // namespace cmcsurf
