// `sscs serve VAULT [--port N] [--host ADDRESS]`: the live design view (cli.md). The vault's check
// report is served on a local port; every file the check read is watched (inotify), and a save
// checks again and pushes the new page into the open browser (Server-Sent Events), which keeps
// its camera and its table's filters. Input errors are shown over the last good view, greyed.
#include <poll.h>
#include <pthread.h>
#include <sys/inotify.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <thread>

#include "cli/subcommands.h"
#include "pipeline/live_check.h"
#include "report/html.h"
#include "report/report.h"
#include "core/digest.h"

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cstring>

#include <httplib.h>  // after Eigen: the macros of the system headers it pulls in confuse Eigen's templates
#include <zlib.h>

namespace sscs::cli {

namespace {

/// What the page adds to a check's report when served: it listens for a new check and reloads,
/// keeping its camera, the table's filters and its scroll position (sessionStorage).
constexpr const char* kLiveScript = R"(
(function () {
  var key = 'sscs-serve-view';
  // The page's controls: its switches (data-testid) and its table's filters (data-filter).
  var controls = 'input[data-testid], select[data-testid], input[data-filter], select[data-filter]';
  function name(e) { return e.hasAttribute('data-testid') ? 'id:' + e.getAttribute('data-testid') : 'filter:' + e.getAttribute('data-filter'); }
  function save() {
    var state = { scroll: [window.scrollX, window.scrollY], inputs: {} };
    var report = window.sscsReport, view = report && report.view;
    if (view && view.orbitCamera && view.controls) {
      state.eye = view.orbitCamera.position.toArray();
      state.target = view.controls.target.toArray();
    }
    document.querySelectorAll(controls).forEach(function (e) {
      state.inputs[name(e)] = e.type === 'checkbox' ? e.checked : e.value;
    });
    try { sessionStorage.setItem(key, JSON.stringify(state)); } catch (e) {}
  }
  function restore() {
    var state;
    try { state = JSON.parse(sessionStorage.getItem(key) || 'null'); } catch (e) { state = null; }
    if (!state) return;
    document.querySelectorAll(controls).forEach(function (e) {
      var id = name(e);
      if (!(id in (state.inputs || {}))) return;
      if (e.type === 'checkbox') { if (e.checked !== state.inputs[id]) { e.checked = state.inputs[id]; e.dispatchEvent(new Event('change')); } }
      else if (e.value !== state.inputs[id]) { e.value = state.inputs[id]; e.dispatchEvent(new Event('input')); e.dispatchEvent(new Event('change')); }
    });
    var report = window.sscsReport, view = report && report.view;
    if (view && state.eye && view.orbitCamera && view.controls) {
      view.orbitCamera.position.fromArray(state.eye);
      view.controls.target.fromArray(state.target);
      view.controls.update();
      if (view.render) view.render();
    }
    if (state.scroll) window.scrollTo(state.scroll[0], state.scroll[1]);
  }
  // After the page's own start (on DOMContentLoaded, registered before this) and its view's load.
  function when_ready() {
    var report = window.sscsReport;
    if (report && report.ready) report.ready.then(function () { setTimeout(restore, 0); }); else restore();
  }
  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', when_ready); else when_ready();
  // Which check the page shows (the server's generation, in a meta element of each page).
  function generation(doc) {
    var m = doc.querySelector('meta[name=sscs-serve-generation]');
    return m ? +m.getAttribute('content') : 0;
  }
  window.sscsServeShown = generation(document);
  // An update is taken in place: the new page fetched, its report data, models and error banner
  // put into this one, and the page built again around the same 3D view (its canvas, camera and
  // switches): no reload, no second start of three.js. A page with no report to take (the first
  // check failed) reloads.
  var busy = false, again = false;
  function replace(selector, doc, where) {
    document.querySelectorAll(selector).forEach(function (e) { e.remove(); });
    doc.querySelectorAll(selector).forEach(function (e) { where(document.importNode(e, true)); });
  }
  // The errors over the page (the banner and its greying style), as the server made them.
  function banner(doc) {
    replace('#sscs-serve-errors', doc, function (e) { document.body.prepend(e); });
    replace('style[data-serve]', doc, function (e) { document.head.appendChild(e); });
  }
  function done(t, shown) {
    t.ready = performance.now();
    restore();
    window.sscsServeTimes = { fetch: t.fetched - t.event, parse: t.parsed - t.fetched, model: t.model - t.parsed, build: t.built - t.model, ready: t.ready - t.built };
    window.sscsServeShown = shown;
  }
  // The whole page fetched: its data, models and banner put into this one.
  function full(t) {
    return fetch('/', { cache: 'no-store' }).then(function (r) { return r.text(); }).then(function (html) {
      t.fetched = performance.now();
      var doc = new DOMParser().parseFromString(html, 'text/html');
      t.parsed = performance.now();
      var data = doc.getElementById('sscs-data'), mine = document.getElementById('sscs-data');
      if (!data || !mine || !window.sscsRebuild) { location.reload(); return; }
      banner(doc);
      var shown = generation(doc);
      // A typo: the last good report stays. (Its model counts too: a save that moves a rack and
      // changes no verdict changes only the model.)
      var models = function (d) { return Array.prototype.map.call(d.querySelectorAll('script[id^=sscs-model-]'), function (e) { return e.textContent; }).join('|'); };
      if (data.textContent === mine.textContent && models(doc) === models(document)) { window.sscsServeShown = shown; return; }
      mine.textContent = data.textContent;
      document.querySelectorAll('script[id^=sscs-model-]').forEach(function (e) { e.remove(); });
      doc.querySelectorAll('script[id^=sscs-model-]').forEach(function (m) {
        var e = document.createElement('script');
        e.type = 'application/octet-stream';
        e.id = m.id;
        e.textContent = m.textContent;
        document.body.appendChild(e);
      });
      t.model = performance.now();
      var rebuilt = window.sscsRebuild();
      t.built = performance.now();
      return rebuilt.then(function () { done(t, shown); });
    });
  }
  // An update is taken in place. A vault's check: the server sends what the save changed (the
  // page's data, and a model of the objects drawn differently, with the names of those gone),
  // put into this page's 3D view; the page is built again around that view (its canvas, camera
  // and switches). A run, or a page too far behind: the whole page (full). A page with no report
  // to take (the first check failed) reloads.
  function update() {
    if (busy) { again = true; return; }
    busy = true;
    save();
    var t = { event: performance.now() };  // how long each part took (web.serve prints it)
    fetch('/update?from=' + window.sscsServeShown, { cache: 'no-store' }).then(function (r) { return r.json(); }).then(function (u) {
      var mine = document.getElementById('sscs-data'), report = window.sscsReport, view = report && report.view;
      if (u.full || !mine || !window.sscsRebuild || !report || report.kind !== 'check' || !view || !view.patchModel) return full(t);
      t.fetched = performance.now();
      banner(new DOMParser().parseFromString('<body>' + (u.banner || '') + '</body>', 'text/html'));
      t.parsed = performance.now();
      if (u.data === mine.textContent && !u.model && !u.removed.length) { window.sscsServeShown = u.generation; return; }
      mine.textContent = u.data;
      view.hold();  // one frame drawn, when the page is rebuilt
      return view.patchModel(u.model, u.removed).then(function () {
        // The view holds the model now; the page's model elements are no longer it.
        document.querySelectorAll('script[id^=sscs-model-]').forEach(function (e) { e.textContent = ''; });
        t.model = performance.now();
        var rebuilt = window.sscsRebuild({ keepModel: true });
        t.built = performance.now();
        return rebuilt.then(function () { done(t, u.generation); });
      }).finally(function () { view.release(); });
    }).catch(function () { location.reload(); }).then(function () {
      busy = false;
      if (again) { again = false; update(); }
    });
  }
  var events = new EventSource('/events');
  events.addEventListener('update', update);
})();
)";

/// The input errors at the top of the page (the diagnostics as printed, without colour), over the
/// last good view greyed when there is one.
std::string errors_banner(const std::string& errors, bool greyed) {
  return fmt::format(
      "<div id=\"sscs-serve-errors\" data-testid=\"serve-errors\" style=\"position:sticky;top:0;z-index:1000;"
      "max-height:45vh;overflow:auto;background:#fff3f3;border-bottom:2px solid #c62828;padding:8px 12px;font:13px monospace\">"
      "<b>sscs serve: the last save does not compile{}</b><pre style=\"margin:6px 0 0;white-space:pre-wrap\">{}</pre></div>{}",
      greyed ? " (the last good view below, greyed)" : "", xml_escape(errors),
      greyed ? "<style data-serve>canvas{filter:grayscale(1) opacity(0.55)}</style>" : "");
}


/// `text` gzipped at zlib's fastest level (the store's 1.2 MB page in about 10 ms), or "" when
/// zlib fails (the page then goes as it is).
std::string gzip_fast(const std::string& text) {
  z_stream z{};
  if (deflateInit2(&z, Z_BEST_SPEED, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) return "";
  std::string out(deflateBound(&z, text.size()) + 32, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  z.avail_in = static_cast<uInt>(text.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  const int done = deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  return done == Z_STREAM_END ? out : "";
}

/// `body` to the browser: gzipped (`gz`, made once) when it takes gzip. (cpp-httplib brotlis a
/// body at each request, at its slowest level: 2.5 s of a save's 2.8 s to the page in chromium. It
/// leaves a content provider's bytes as they are.)
void send(const httplib::Request& req, httplib::Response& res, const std::string& gz, const std::string& body, const char* type) {
  if (!gz.empty() && req.get_header_value("Accept-Encoding").find("gzip") != std::string::npos) {
    auto bytes = std::make_shared<const std::string>(gz);
    res.set_header("Content-Encoding", "gzip");
    res.set_content_provider(bytes->size(), type, [bytes](size_t offset, size_t length, httplib::DataSink& sink) {
      return sink.write(bytes->data() + offset, length);
    });
    return;
  }
  res.set_content(body, type);
}

/// The live state: what the page of the last check published (its generation) is made of. A
/// vault's page is made when a browser asks for it; a save's changes alone are sent to an open page.
struct Live {
  std::mutex m;
  std::condition_variable published, changed;
  long generation = 0;
  std::shared_ptr<const LiveVault> vault;  ///< the last vault check that compiled
  std::string banner;     ///< the last save's input errors, over that check ("" when it compiled)
  std::string run_page;   ///< otherwise: a run's page, or the errors alone (with its live script)
  std::string last_run;   ///< the last run's page that compiled, as made
  /// The objects each recent generation's page draws (vault checks): what a save changed for a
  /// page that shows that generation.
  std::map<long, std::shared_ptr<const LiveVault::Keys>> keys_at;
  long page_generation = -1;  ///< the generation `page` was made for
  std::string page;
  std::string page_gz;        ///< `page` gzipped (fast), for browsers
  bool dirty = true;      ///< a watched file changed since the last check began
  bool stopping = false;
  std::vector<std::string> files;  ///< watched
  long watch_generation = 0;       ///< bumped when `files` changes
  std::atomic<bool> checking{false};  ///< a check under way (one that never ends does not hold up Ctrl-C)
  std::atomic<bool> cancel{false};    ///< a save made while a check runs: that check stops, the save is checked
};

std::string generation_meta(long generation) {
  return fmt::format("<meta name=\"sscs-serve-generation\" content=\"{}\">", generation);
}

/// The page of the generation published, made now if it was not (the lock held).
void make_page(Live& live) {
  if (live.page_generation == live.generation) return;
  live.page = live.vault ? with_live_script(live.vault->page(), kLiveScript, generation_meta(live.generation) + live.banner)
                         : live.run_page;
  live.page_gz = gzip_fast(live.page);
  live.page_generation = live.generation;
}

/// Checks again on every change: the last save wins (a check begun before it is not published).
/// `run`: the file is a scenario or a campaign, run into `scratch` at each change.
void checker(Live& live, const std::string& vault, const CompileOptions& options, bool quiet, bool run, const std::string& scratch) {
  LibraryCache library;  // a save of the vault checks the vault, not the library again
  for (;;) {
    {
      std::unique_lock lock(live.m);
      live.changed.wait(lock, [&] { return live.dirty || live.stopping; });
      if (live.stopping) return;
    }
    // A burst of writes (an editor's save, a formatter after it) is one change.
    std::this_thread::sleep_for(std::chrono::milliseconds(40));
    {
      std::lock_guard lock(live.m);
      live.dirty = false;
    }
    const auto t0 = std::chrono::steady_clock::now();
    live.checking = true;
    live.cancel = false;
    LiveCheck result;
    try {
      result = run ? live_run(vault, options, scratch) : live_check(vault, options, library, &live.cancel);
    } catch (const CheckCancelled&) {
      live.checking = false;
      continue;  // a newer save: checked next (the last save wins, without waiting for this one)
    }
    live.checking = false;
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::shared_ptr<const LiveVault> retired;  // the check it replaces, freed after the lock (10,000 objects: tens of ms)
    std::lock_guard lock(live.m);
    if (live.stopping) return;
    if (live.dirty) continue;  // saved again meanwhile: that save's check is the one shown
    const long next = live.generation + 1;
    // Which check a page shows: its live script takes updates in place and tells the tests.
    const std::string meta = generation_meta(next);
    live.banner.clear();
    live.run_page.clear();
    if (result.vault) {
      retired = std::move(live.vault);
      live.vault = result.vault;
    } else if (result.compiled) {
      live.last_run = result.page;
      live.run_page = with_live_script(result.page, kLiveScript, meta);
    } else if (live.vault) {
      live.banner = errors_banner(result.errors, true);
    } else if (!live.last_run.empty()) {
      live.run_page = with_live_script(live.last_run, kLiveScript, meta + errors_banner(result.errors, true));
    } else {
      live.run_page = fmt::format("<!doctype html><html><head><meta charset=\"utf-8\"><title>sscs serve</title></head><body>{}<script>{}</script></body></html>",
                                  errors_banner(result.errors, false), kLiveScript);
    }
    if (result.files != live.files) {
      live.files = result.files;
      ++live.watch_generation;
    }
    live.generation = next;
    if (live.vault && live.run_page.empty()) {
      live.keys_at[next] = live.vault->keys();
      while (live.keys_at.size() > 4) live.keys_at.erase(live.keys_at.begin());
    } else {
      live.keys_at.clear();
    }
    if (!live.run_page.empty()) make_page(live);  // (a vault's page is made when asked for)
    live.published.notify_all();
    if (!quiet) std::cout << fmt::format("sscs serve: checked in {:.0f} ms: {}\n", ms, result.summary) << std::flush;
  }
}

/// Watches the folders of the files the last check read; a change to one of them (written,
/// replaced by a rename as editors save, created, removed) marks the state dirty.
void watcher(Live& live) {
  const int fd = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd < 0) return;
  std::map<int, std::string> folders;  // watch descriptor -> folder
  std::set<std::string> names;         // the files watched
  long seen = -1;
  std::vector<char> buffer(64 * 1024);
  for (;;) {
    {
      std::lock_guard lock(live.m);
      if (live.stopping) break;
      if (seen != live.watch_generation) {
        seen = live.watch_generation;
        for (const auto& [wd, folder] : folders) inotify_rm_watch(fd, wd);
        folders.clear();
        names = std::set<std::string>(live.files.begin(), live.files.end());
        std::set<std::string> dirs;
        for (const std::string& f : live.files) dirs.insert(std::filesystem::path(f).parent_path().string());
        for (const std::string& d : dirs) {
          const int wd = inotify_add_watch(fd, d.c_str(), IN_CLOSE_WRITE | IN_MOVED_TO | IN_CREATE | IN_DELETE | IN_MODIFY);
          if (wd >= 0) folders[wd] = d;
        }
      }
    }
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 200) <= 0) continue;
    const ssize_t n = read(fd, buffer.data(), buffer.size());
    bool hit = false;
    for (ssize_t at = 0; at < n;) {
      const auto* e = reinterpret_cast<const inotify_event*>(buffer.data() + at);
      if (e->len > 0 && folders.count(e->wd) && names.count((std::filesystem::path(folders[e->wd]) / e->name).string())) hit = true;
      at += static_cast<ssize_t>(sizeof(inotify_event) + e->len);
    }
    if (hit) {
      std::lock_guard lock(live.m);
      live.dirty = true;
      live.cancel = true;  // a check under way is of an older save
      live.changed.notify_all();
    }
  }
  close(fd);
}

}  // namespace

int run_serve(const Common& common, const ServeArgs& args) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_regular_file(args.file, ec)) {
    std::cerr << fmt::format("sscs: error: {}: no such file\n", args.file);
    return kInputError;
  }
  bool run = false;  // a scenario or a campaign: run at each save, its run's report served
  {
    std::ifstream in(args.file);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    static const std::regex kind(R"((^|\n)(scenario|campaign)\s*:)");
    run = std::regex_search(text, kind);
  }
  if (args.port < 0 || args.port > 65535) {
    std::cerr << fmt::format("sscs: error: --port expects 0 to 65535, found {}\n", args.port);
    return kInputError;
  }
  CompileOptions options;
  if (!common.apply(options, {args.file})) return kInputError;

  // Ctrl-C and SIGTERM stop the server: waited for by a thread of its own (blocked in all others).
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  Live live;
  httplib::Server server;
  server.Get("/", [&](const httplib::Request& req, httplib::Response& res) {
    std::unique_lock lock(live.m);
    // The first check: wait for it (a page that is not there yet would say nothing).
    live.published.wait_for(lock, std::chrono::seconds(30), [&] { return live.generation > 0 || live.stopping; });
    res.set_header("Cache-Control", "no-store");
    if (live.generation > 0) make_page(live);
    send(req, res, live.page_gz, live.page.empty() ? std::string("sscs serve: still checking; reload in a moment") : live.page,
         "text/html; charset=utf-8");
  });
  // What an open page showing generation `from` takes of the last check: the page's data, the
  // errors over it, and a model of the objects drawn differently (new or changed) with the names
  // of those gone; {"full": true} when it must fetch the page (a run, a generation not kept).
  server.Get("/update", [&](const httplib::Request& req, httplib::Response& res) {
    std::unique_lock lock(live.m);
    res.set_header("Cache-Control", "no-store");
    long from = -1;
    try {
      from = std::stol(req.get_param_value("from"));
    } catch (const std::exception&) {
    }
    nlohmann::json out;
    auto before = live.keys_at.find(from);
    if (!live.vault || !live.run_page.empty() || before == live.keys_at.end()) {
      out = {{"full", true}};
    } else {
      std::vector<std::string> removed;
      const std::string model = live.vault->changed_model(*before->second, removed);
      out = {{"generation", live.generation}, {"banner", live.banner}, {"data", live.vault->data()}, {"removed", removed},
             {"model", model.empty() ? std::string() : base64(model)}};
    }
    const std::string body = out.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    lock.unlock();
    send(req, res, gzip_fast(body), body, "application/json");
  });
  server.Get("/events", [&](const httplib::Request&, httplib::Response& res) {
    long sent = -1;
    res.set_header("Cache-Control", "no-store");
    res.set_chunked_content_provider("text/event-stream", [&live, sent](size_t, httplib::DataSink& sink) mutable {
      std::unique_lock lock(live.m);
      if (sent < 0) sent = live.generation;  // what the page shows now
      live.published.wait_for(lock, std::chrono::seconds(15), [&] { return live.generation != sent || live.stopping; });
      if (live.stopping) {
        sink.done();
        return false;
      }
      std::string message = live.generation != sent ? fmt::format("event: update\ndata: {}\n\n", live.generation) : ": alive\n\n";
      sent = live.generation;
      lock.unlock();
      return sink.write(message.data(), message.size());
    });
  });
  server.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.status == 404) res.set_content("sscs serve: only the page (/) and its updates (/events, /update) are served\n", "text/plain");
  });

  const int port = args.port == 0 ? server.bind_to_any_port(args.host) : (server.bind_to_port(args.host, args.port) ? args.port : -1);
  if (port < 0) {
    std::cerr << fmt::format("sscs: error: cannot listen on {}:{} (in use, or not an address of this machine)\n", args.host, args.port);
    return kInputError;
  }
  // A scenario's runs go to a folder of the server's own, removed when it stops.
  std::string scratch;
  if (run) {
    std::string pattern = (fs::temp_directory_path() / "sscs-serve-XXXXXX").string();
    if (!mkdtemp(pattern.data())) {
      std::cerr << fmt::format("sscs: error: cannot make a folder for the runs in {}: {}\n", fs::temp_directory_path().string(), std::strerror(errno));
      return kInputError;
    }
    scratch = pattern;
    common.confine_to_projects({project_root_of(args.file), scratch});  // the run's resolved/ files are read back from there
  }
  struct RemoveScratch {
    std::string dir;
    ~RemoveScratch() {
      std::error_code ec;
      if (!dir.empty()) fs::remove_all(dir, ec);
    }
  } remove_scratch{scratch};
  std::thread check_thread(checker, std::ref(live), fs::absolute(args.file).string(), options, common.quiet, run, scratch);
  std::thread watch_thread(watcher, std::ref(live));
  std::thread http_thread([&] { server.listen_after_bind(); });
  std::cout << fmt::format("sscs serve: http://{}:{}/ shows {}; every file its check reads is watched (Ctrl-C stops)\n",
                           args.host.find(':') != std::string::npos ? "[" + args.host + "]" : args.host, port, args.file)
            << std::flush;
  int signal = 0;
  sigwait(&stop_signals, &signal);
  {
    std::lock_guard lock(live.m);
    live.stopping = true;
    live.changed.notify_all();
    live.published.notify_all();
  }
  server.stop();
  http_thread.join();
  watch_thread.join();
  // A check under way ends by itself; one that hangs (a vault that never finishes compiling) is
  // left behind: the process ends without it.
  for (int k = 0; k < 100 && live.checking; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  if (live.checking) {
    std::cout << std::flush;
    std::_Exit(kOk);
  }
  check_thread.join();
  return kOk;
}

}  // namespace sscs::cli
