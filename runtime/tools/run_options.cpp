#include "run_options.h"

#include <charconv>
#include <cmath>
#include <string_view>

namespace probebake::run {
namespace {

constexpr const char* kUsage =
    "usage: probebake-run FILE.probes [--frames N] [--csv OUT.csv] [--validate] [--vk-validation]\n"
    "                     [--device NAME] [--samples N [--compare-all-probes]] [--hysteresis H]\n"
    "                     [--probe-code float|l2|l1]\n"
    "                     [--no-light-update] [--depth-cycle LOW:HIGH:PERIOD] [--orbit-light I:RADIUS:PERIOD]\n"
    "                     [--animate thesis|revolution|soak [--plots DIR] [--objects LIST]] [--memory-update]\n"
    "                     [--no-memory-update] [--max-depth N] [--pool-probes N]\n"
    "                     [--limits M:L] [--gather-budget N] [--trace-budget N] [--frame-ms MS]\n"
    "                     [--load-focus X,Y,Z]\n"
    "                     [--shadow-rays N] [--verbose]\n"
    "                     [--budget BYTES --path PATH.csv [--radius R] [--max-upload BYTES] [--max-joining N]\n"
    "                      [--keep-margin M] [--max-lit N] [--light-reach M] [--background-reads]]\n"
    "  --frames N        frames to run (default 1; with --animate the animation's 600, soak 10000)\n"
    "  --csv OUT.csv     write frame,pass,gpu_ms,cpu_ms,live_probes,probe_capacity,lit_probes,\n"
    "                    indirect_misses,non_finite,splits,merges,failed_allocations,free_probes,\n"
    "                    lights,uploaded_lights,light_x,light_y,light_z per pass; with --animate one row\n"
    "                    per frame (docs/RUNTIME.md \"Animated runs\")\n"
    "  --animate NAME    turn the file's dynamic objects (thesis: 45 degrees over frames 200-350; revolution:\n"
    "                    a turn in 150 frames, 50 still, three times; soak: random motion); memory update on\n"
    "  --plots DIR       with --animate: SVG plots of the per-frame table into DIR\n"
    "  --objects LIST    with --animate: move only these dynamic objects (comma-separated indices from 0)\n"
    "  --no-memory-update  keep the octree fixed even with --animate (moved objects re-trace only the probes\n"
    "                    whose rays cross them)\n"
    "  --memory-update   reshape the octree on the GPU (octree volumes with lighting sections)\n"
    "  --max-depth N     with the memory update: the leaf rule's max depth from frame 0 (0-12)\n"
    "  --limits M:L      with the memory update: at most M allocations and L lit leaves per frame (0 = all)\n"
    "  --pool-probes N   with the memory update: N free probe slots (and their light records) at upload\n"
    "                    (default: as many as in use, at least 512; streaming: sized by the budget)\n"
    "  --gather-budget N without the memory update: gather N probes per frame, a window of probe slots\n"
    "                    that moves on every frame (0 = all, the default)\n"
    "  --trace-budget N  trace the loaded probes' light records N probe slots per frame, in slot order,\n"
    "                    instead of all in frame 0 (0 = all, the default); a probe keeps the bake's\n"
    "                    irradiance until its records exist\n"
    "  --load-focus X,Y,Z  with --trace-budget or --frame-ms: trace the probes nearest this point first\n"
    "                    (with --path: the path's first point unless given)\n"
    "  --frame-ms MS     while the load trace lasts, trace as many slots per frame as fit in MS of GPU time\n"
    "                    beside the other passes (measured and corrected every frame; replaces --trace-budget)\n"
    "  --shadow-rays N   shadow rays per lighting record for a whole punctual sum (0 = one per light, the\n"
    "                    default; 2-9: the strongest N - 1 lights exact, one of the others sampled)\n"
    "  --relight-frames N  the sky and a light that changes every frame (the --day-cycle sun) relight a probe\n"
    "                    every N frames, 1/N of them a frame (1-64; default 1; FrameLimits::relight_frames)\n"
    "  --budget BYTES    stream the cells' tracing blocks within BYTES of device memory (K, M, G suffixes;\n"
    "                    needs --path and a file baked with --cell-size): one frame per path row, a line per\n"
    "                    frame and the worst upload spike (docs/RUNTIME.md \"Streaming cells\")\n"
    "  --path PATH.csv   the camera: frame,x,y,z rows (a header line frame,x,y,z first)\n"
    "  --radius R        with --path: cells within R metres of the camera are wanted (default 20)\n"
    "  --max-upload B    with --path: copy at most B bytes per frame (0 = no limit, the default)\n"
    "  --max-joining N   with --path: at most N probes of arrived cells start being lit (traced) per frame\n"
    "  --keep-margin M   with --path: resident cells stay while within R + M metres (default 0)\n"
    "  --max-lit N       with --path: light records for N probes at once (default: every probe)\n"
    "  --light-reach M   with --path: light a cell's probes only once every cell within M metres is resident\n"
    "                    (default 0: once the cell is)\n"
    "  --background-reads  with --path: read arriving cells from the file on a thread of their own (a cell\n"
    "                    arrives a frame or more after it is wanted; frames never wait for the disk)\n"
    "  --verbose         one line per frame (default: a progress bar on a terminal, else a line every 100\n"
    "                    frames)\n"
    "  --validate        read the live state back and run the .probes validator after every frame\n"
    "  --vk-validation   enable VK_LAYER_KHRONOS_validation (synchronization validation on)\n"
    "  --device NAME     use the first Vulkan device whose name contains NAME\n"
    "  --samples N       after the frames, time N irradiance lookups at random points\n"
    "  --compare-all-probes  also time the all-probe loop (thesis 3.2.4) on the same points\n"
    "  --hysteresis H    weight of the old irradiance per frame, in [0, 1) (default 0.9)\n"
    "  --probe-code C    the probes the lookups read: float (the records, default), l2 (48 bytes a probe) or l1\n"
    "                    (32 bytes, band 2 dropped), encoded after every frame (docs/RUNTIME.md \"Compact probes\")\n"
    "  --no-light-update keep the baked irradiance (no light passes, no light buffers)\n"
    "  --depth-cycle LOW:HIGH:PERIOD  run the memory update (octree volumes with lighting sections);\n"
    "                    every PERIOD frames the max depth alternates HIGH, LOW, ... and every leaf is\n"
    "                    measured again\n"
    "  --orbit-light I:RADIUS:PERIOD  move the file's punctual light I (from 0; `all`: every light) on a horizontal "
    "circle of\n"
    "                    RADIUS metres through its baked position, one turn every PERIOD frames (a\n"
    "                    directional light turns its direction about Y); light_x/y/z in the CSV\n"
    "  --day-cycle SECONDS  a volume baked with --sky physical: the sun crosses the sky from 6:00 (east, +X) over\n"
    "                    60 degrees (towards +Z) to 18:00, one day every SECONDS at 60 frames a second; the\n"
    "                    sky map and the sun change every frame (docs/RUNTIME.md \"Sky and time of day\")\n"
    "  --switch-emitters PERIOD  every emitter (emissive material) off from frame PERIOD, on again from 2 PERIOD,\n"
    "                    and so on (docs/RUNTIME.md \"Emitters at run time\"); emitters_on in the CSV\n"
    "exit codes: 0 ok, 1 usage, 2 bad input file, 4 runtime or validation failure, 5 the device did not\n"
    "finish a frame within 60 s (spread the load trace: --trace-budget or --frame-ms)\n";

bool parse_int(std::string_view text, int minimum, int& out) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), out);
  return error == std::errc() && end == text.data() + text.size() && out >= minimum;
}

bool parse_number(std::string_view text, float& out) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), out);
  return error == std::errc() && end == text.data() + text.size();
}

// A byte count with an optional K, M or G suffix (powers of 1024).
bool parse_bytes(std::string_view text, std::uint64_t& out) {
  std::uint64_t scale = 1;
  if (!text.empty() && (text.back() == 'K' || text.back() == 'M' || text.back() == 'G')) {
    scale = text.back() == 'K' ? 1ull << 10 : text.back() == 'M' ? 1ull << 20 : 1ull << 30;
    text.remove_suffix(1);
  }
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), out);
  if (error != std::errc() || end != text.data() + text.size() || out > (~0ull) / scale) return false;
  out *= scale;
  return true;
}

bool parse_fraction(std::string_view text, float& out) { return parse_number(text, out) && out >= 0.0f && out < 1.0f; }

// LOW:HIGH:PERIOD, depths in [0, 12], period >= 1.
bool parse_depth_cycle(std::string_view text, DepthCycle& out) {
  const std::size_t a = text.find(':'), b = a == std::string_view::npos ? a : text.find(':', a + 1);
  if (b == std::string_view::npos) return false;
  return parse_int(text.substr(0, a), 0, out.low) && parse_int(text.substr(a + 1, b - a - 1), 0, out.high) &&
         parse_int(text.substr(b + 1), 1, out.period) && out.low <= 12 && out.high <= 12;
}

// M:L, both >= 0.
bool parse_limits(std::string_view text, runtime::FrameLimits& out) {
  const std::size_t a = text.find(':');
  return a != std::string_view::npos && parse_int(text.substr(0, a), 0, out.max_memory_entries) &&
         parse_int(text.substr(a + 1), 0, out.max_light_entries);
}

// I:RADIUS:PERIOD, light index >= 0 or `all`, radius finite and >= 0, period >= 1.
bool parse_light_orbit(std::string_view text, LightOrbit& out) {
  const std::size_t a = text.find(':'), b = a == std::string_view::npos ? a : text.find(':', a + 1);
  if (b == std::string_view::npos) return false;
  const std::string_view radius = text.substr(a + 1, b - a - 1);
  const auto [end, error] = std::from_chars(radius.data(), radius.data() + radius.size(), out.radius);
  const bool radius_ok =
      error == std::errc() && end == radius.data() + radius.size() && std::isfinite(out.radius) && out.radius >= 0.0f;
  const bool every_light = text.substr(0, a) == "all";
  if (every_light) out.light = LightOrbit::kEveryLight;
  return radius_ok && (every_light || parse_int(text.substr(0, a), 0, out.light)) &&
         parse_int(text.substr(b + 1), 1, out.period);
}

// X,Y,Z, finite.
bool parse_point(std::string_view text, glm::vec3& out) {
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t comma = axis < 2 ? text.find(',') : text.size();
    if (comma == std::string_view::npos || !parse_number(text.substr(0, comma), out[axis]) || !std::isfinite(out[axis]))
      return false;
    text = axis < 2 ? text.substr(comma + 1) : std::string_view();
  }
  return true;
}

} // namespace

std::optional<RunOptions> parse_run_options(int argc, char** argv, std::string& message, int& exit_code) {
  RunOptions options;
  bool frames_given = false;
  exit_code = 1;
  // The usage and errors name the program that parses: probebake-run, or `probebake run` (argv[0]).
  std::string program = argc > 0 && argv[0] != nullptr ? argv[0] : "probebake-run";
  program = program.substr(program.find_last_of('/') + 1); // find_last_of gives npos + 1 = 0 without a '/'
  std::string usage = kUsage;
  usage.replace(usage.find("probebake-run"), std::string_view("probebake-run").size(), program);
  auto usage_error = [&](const std::string& what) {
    message = program + ": " + what + "\n" + usage;
    return std::nullopt;
  };
  // The --budget/--path group's options, made on first use.
  const auto stream = [&]() -> StreamRun& { return options.stream ? *options.stream : options.stream.emplace(); };
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--help" || arg == "-h") {
      message = usage;
      exit_code = 0;
      return std::nullopt;
    } else if (arg == "--validate") {
      options.validate = true;
    } else if (arg == "--compare-all-probes") {
      options.compare_all_probes = true;
    } else if (arg == "--no-light-update") {
      options.light_update = false;
    } else if (arg == "--probe-code") {
      const auto codec = has_value ? formats::parse_sh_codec(argv[++i]) : std::nullopt;
      if (!codec) return usage_error("--probe-code needs float, l2 or l1");
      options.probe_code = *codec;
    } else if (arg == "--hysteresis") {
      if (!has_value || !parse_fraction(argv[++i], options.hysteresis))
        return usage_error("--hysteresis needs a number in [0, 1)");
    } else if (arg == "--depth-cycle") {
      DepthCycle cycle;
      if (!has_value || !parse_depth_cycle(argv[++i], cycle))
        return usage_error("--depth-cycle needs LOW:HIGH:PERIOD (depths 0-12, period >= 1)");
      options.depth_cycle = cycle;
    } else if (arg == "--orbit-light") {
      LightOrbit orbit;
      if (!has_value || !parse_light_orbit(argv[++i], orbit))
        return usage_error(
            "--orbit-light needs I:RADIUS:PERIOD (light index >= 0 or all, radius >= 0 metres, period >= 1 frames)");
      options.orbit_light = orbit;
    } else if (arg == "--day-cycle") {
      float seconds = 0.0f;
      if (!has_value || !parse_number(argv[++i], seconds) || !(seconds > 0.0f) || !std::isfinite(seconds))
        return usage_error("--day-cycle needs SECONDS > 0 (a day's length at 60 frames a second)");
      options.day_cycle = seconds;
    } else if (arg == "--switch-emitters") {
      int period = 0;
      if (!has_value || !parse_int(argv[++i], 1, period))
        return usage_error("--switch-emitters needs PERIOD >= 1 (frames between switches)");
      options.switch_emitters = period;
    } else if (arg == "--vk-validation") {
      options.vulkan_validation = true;
    } else if (arg == "--memory-update") {
      options.memory_update = true;
    } else if (arg == "--no-memory-update") {
      options.no_memory_update = true;
    } else if (arg == "--objects") {
      if (!has_value) return usage_error("--objects needs a comma-separated list of object indices");
      std::string_view list = argv[++i];
      while (!list.empty()) {
        const std::size_t comma = std::min(list.find(','), list.size());
        int object = 0;
        if (!parse_int(list.substr(0, comma), 0, object))
          return usage_error("--objects needs a comma-separated list of object indices >= 0");
        options.animated_objects.push_back(object);
        list.remove_prefix(std::min(comma + 1, list.size()));
      }
    } else if (arg == "--verbose") {
      options.verbose = true;
    } else if (arg == "--animate") {
      if (!has_value || !(options.animate = dynamic::parse_animation(argv[++i])))
        return usage_error("--animate needs thesis, revolution or soak");
    } else if (arg == "--max-depth") {
      int depth = 0;
      if (!has_value || !parse_int(argv[++i], 0, depth) || depth > 12)
        return usage_error("--max-depth needs a depth in 0-12");
      options.max_depth = depth;
    } else if (arg == "--pool-probes") {
      int probes = 0;
      if (!has_value || !parse_int(argv[++i], 0, probes))
        return usage_error("--pool-probes needs a whole number of probes >= 0");
      options.pool_probes = probes;
    } else if (arg == "--limits") {
      if (!has_value || !parse_limits(argv[++i], options.limits))
        return usage_error("--limits needs M:L (whole numbers >= 0)");
    } else if (arg == "--gather-budget") {
      if (!has_value || !parse_int(argv[++i], 0, options.limits.max_gathered_probes))
        return usage_error("--gather-budget needs a whole number of probes >= 0");
    } else if (arg == "--trace-budget") {
      if (!has_value || !parse_int(argv[++i], 0, options.limits.max_traced_probes))
        return usage_error("--trace-budget needs a whole number of probe slots >= 0");
    } else if (arg == "--load-focus") {
      glm::vec3 focus;
      if (!has_value || !parse_point(argv[++i], focus)) return usage_error("--load-focus needs X,Y,Z in metres");
      options.load_focus = focus;
    } else if (arg == "--frame-ms") {
      float& ms = options.limits.frame_ms;
      if (!has_value || !parse_number(argv[++i], ms) || !(ms > 0.0f && ms <= 1e6f))
        return usage_error("--frame-ms needs a time in milliseconds in (0, 1e6]");
    } else if (arg == "--shadow-rays") {
      int& rays = options.limits.shadow_rays_per_record;
      if (!has_value || !parse_int(argv[++i], 0, rays) || rays == 1 || rays > 9)
        return usage_error("--shadow-rays needs 0 or a number in 2-9");
    } else if (arg == "--relight-frames") {
      int& frames = options.limits.relight_frames;
      if (!has_value || !parse_int(argv[++i], 1, frames) || frames > 64)
        return usage_error("--relight-frames needs a number of frames in 1-64");
    } else if (arg == "--budget" || arg == "--max-upload") {
      std::uint64_t& bytes = arg == "--budget" ? stream().budget : stream().max_upload;
      if (!has_value || !parse_bytes(argv[++i], bytes) || (arg == "--budget" && bytes == 0))
        return usage_error(std::string(arg) + " needs a byte count like 65536, 512K or 64M" +
                           (arg == "--budget" ? " (> 0)" : ""));
    } else if (arg == "--max-joining" || arg == "--max-lit") {
      int& probes = arg == "--max-joining" ? stream().max_joining : stream().max_lit;
      if (!has_value || !parse_int(argv[++i], 0, probes))
        return usage_error(std::string(arg) + " needs a whole number of probes >= 0");
    } else if (arg == "--keep-margin" || arg == "--radius" || arg == "--light-reach") {
      float& metres = arg == "--radius"        ? stream().radius
                      : arg == "--keep-margin" ? stream().keep_margin
                                               : stream().light_reach;
      if (!has_value || !parse_number(argv[++i], metres) || !(metres >= 0.0f) || !std::isfinite(metres))
        return usage_error(std::string(arg) + " needs a finite number of metres >= 0");
    } else if (arg == "--background-reads") {
      stream().background_reads = true;
    } else if (arg == "--path") {
      if (!has_value) return usage_error("--path needs a CSV file (frame,x,y,z)");
      stream().path = argv[++i];
    } else if (arg == "--plots") {
      if (!has_value) return usage_error("--plots needs a folder");
      options.plots = argv[++i];
    } else if (arg == "--frames" || arg == "--samples") {
      int value = 0;
      if (!has_value || !parse_int(argv[++i], arg == "--frames" ? 1 : 0, value))
        return usage_error(std::string(arg) + " needs a whole number" + (arg == "--frames" ? " >= 1" : " >= 0"));
      (arg == "--frames" ? options.frames : options.samples) = value;
      frames_given = frames_given || arg == "--frames";
    } else if (arg == "--csv" || arg == "--device") {
      if (!has_value) return usage_error(std::string(arg) + " needs a value");
      (arg == "--csv" ? options.csv.emplace() : options.device) = argv[++i];
    } else if (!arg.empty() && arg[0] == '-') {
      return usage_error("unknown option " + std::string(arg));
    } else if (options.input.empty()) {
      options.input = arg;
    } else {
      return usage_error("more than one input file");
    }
  }
  if (options.input.empty()) return usage_error("no input file");
  if (options.stream && (options.stream->budget == 0 || options.stream->path.empty()))
    return usage_error("--budget and --path go together (and --radius, --max-upload need them)");
  const bool memory_update =
      !options.no_memory_update && (options.animate || options.depth_cycle || options.memory_update);
  if (options.stream && memory_update && (options.stream->max_lit > 0 || options.stream->light_reach > 0.0f))
    return usage_error(
        "--max-lit and --light-reach describe a fixed tree: the memory update (--memory-update, --animate, "
        "--depth-cycle) lights every probe of its tree");
  if (options.animate && !frames_given) options.frames = dynamic::default_frames(*options.animate);
  return options;
}

} // namespace probebake::run
