// The HTTP server of `camplace serve` on cpp-httplib (server.hpp).
#include "camplace/serve/server.hpp"

#include <httplib.h>
#include <sys/socket.h>

#include <array>
#include <chrono>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>
#include <utility>

#include "camplace/core/error.hpp"
#include "camplace/core/json_reader.hpp"
#include "jobs.hpp"
#include "planner_page.hpp"

namespace camplace::serve {

namespace {

using json = nlohmann::json;

/// The three.js files the page loads: URL path → file under libjs-three's directory.
const std::array<std::pair<const char*, const char*>, 3> kThreeFiles{{
    {"/three/three.min.js", "three.min.js"},
    {"/three/OrbitControls.js", "examples/js/controls/OrbitControls.js"},
    {"/three/TransformControls.js", "examples/js/controls/TransformControls.js"},
}};

std::string random_token() {
  std::random_device device;
  std::string token;
  const char* digits = "0123456789abcdef";
  for (int i = 0; i < 32; ++i) token += digits[device() % 16];
  return token;
}

/// Compares in time independent of where the strings differ (the token is a secret).
bool same_secret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// JSON with its charset: cpp-httplib compresses only the bare "application/json", and a
/// brotli-compressed view costs about 200 ms, twice the whole round trip on the loopback.
void send_json(httplib::Response& res, const json& j) {
  res.set_content(j.dump(), "application/json; charset=utf-8");
}

/// A refused request: the status and the `error:` line the command line would print.
void send_error(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content("error: " + message + "\n", "text/plain; charset=utf-8");
}

/// The request body as JSON ({} when empty), read as files are read (a key twice is an error).
json body_json(const httplib::Request& req) {
  if (req.body.empty()) return json::object();
  return core::parse_json_text(req.body, "request");
}

/// The integer member `key` of `body` in [lo, hi], or `fallback` when absent.
int int_member(const json& body, const std::string& key, int lo, int hi, int fallback) {
  const core::JsonNode root(body, "request", "");
  if (!body.is_object()) root.fail("expected a JSON object");
  return root.has(key) ? root.at(key).integer_in(lo, hi) : fallback;
}

/// The query parameter `key` as an integer in [lo, hi], or `fallback` when absent.
int int_param(const httplib::Request& req, const std::string& key, int lo, int hi, int fallback) {
  if (!req.has_param(key.c_str())) return fallback;
  const std::string text = req.get_param_value(key.c_str());
  std::size_t used = 0;
  long value = 0;
  try {
    value = std::stol(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || value < lo || value > hi) {
    throw core::InputError("request", "?" + key,
                           "expected an integer in [" + std::to_string(lo) + ", " +
                               std::to_string(hi) + "], got \"" + text + "\"");
  }
  return static_cast<int>(value);
}

}  // namespace

struct Server::Impl {
  Planner& planner;
  ServerOptions options;
  httplib::Server http;
  detail::Jobs jobs;
  int port = 0;
  std::atomic<bool> stopping{false};

  Impl(Planner& p, ServerOptions o) : planner(p), options(std::move(o)), jobs(p) {}

  /// Runs `handler`, answering bad input with 400 and the error line, anything else with 500.
  template <class Handler>
  void guarded(httplib::Response& res, Handler&& handler) {
    try {
      handler();
    } catch (const core::InputError& e) {
      send_error(res, 400, e.what());
    } catch (const std::exception& e) {
      send_error(res, 500, std::string("internal: ") + e.what());
    }
  }

  void routes() {
    http.new_task_queue = [threads = options.threads] {
      return new httplib::ThreadPool(static_cast<std::size_t>(threads));
    };
    http.set_payload_max_length(options.max_request_bytes);
    // SO_REUSEADDR (a restarted server gets its port back at once) but not cpp-httplib's
    // default SO_REUSEPORT, with which a second `camplace serve` on the same port would start
    // and share the requests with the first instead of failing.
    http.set_socket_options([](socket_t sock) {
      int yes = 1;
      setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    // Headers and body go out as separate writes: without TCP_NODELAY, Nagle's algorithm and
    // the browser's delayed ACK hold the body back by up to 40 ms per answer.
    http.set_tcp_nodelay(true);
    // Every request carries the token (query or header), also the page and its scripts: another
    // local user, or a web page in the same browser, cannot drive the planner without it.
    http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      const std::string given = req.has_param("token") ? req.get_param_value("token")
                                                       : req.get_header_value("X-Camplace-Token");
      if (same_secret(given, options.token)) return httplib::Server::HandlerResponse::Unhandled;
      send_error(res, 403,
                 "request: " + std::string(given.empty() ? "no" : "wrong") +
                     " token: open the URL camplace serve printed (it holds the token)");
      return httplib::Server::HandlerResponse::Handled;
    });
    http.set_error_handler(httplib::Server::HandlerWithResponse([](const httplib::Request& req,
                                                                   httplib::Response& res) {
      if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
      if (res.status == 413) {
        send_error(res, 413, "request: the request body is larger than the server accepts");
      } else if (res.status == 404) {
        send_error(res, 404, "request: " + req.path + ": no such page or API call");
      } else {
        send_error(res, res.status, "request: refused (HTTP " + std::to_string(res.status) + ")");
      }
      return httplib::Server::HandlerResponse::Handled;
    }));
    http.set_exception_handler(
        [](const httplib::Request&, httplib::Response& res, std::exception_ptr error) {
          try {
            std::rethrow_exception(error);
          } catch (const core::InputError& e) {
            send_error(res, 400, e.what());
          } catch (const std::exception& e) {
            send_error(res, 500, std::string("internal: ") + e.what());
          } catch (...) {
            send_error(res, 500, "internal: unknown exception");
          }
        });

    http.Get("/", [](const httplib::Request&, httplib::Response& res) {
      res.set_header("Cache-Control", "no-store");
      res.set_content(detail::planner_page(), "text/html; charset=utf-8");
    });
    for (const auto& [path, file] : kThreeFiles) {
      const std::string content = read_file(options.three_dir + "/" + file);
      http.Get(path, [content](const httplib::Request&, httplib::Response& res) {
        // Not "text/...": cpp-httplib would compress 600 kB with brotli on every load.
        res.set_content(content, "application/javascript; charset=utf-8");
      });
    }
    http.Get("/api/scene", [this](const httplib::Request&, httplib::Response& res) {
      guarded(res, [&] { send_json(res, planner.scene_json()); });
    });
    http.Get("/api/view", [this](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] { send_json(res, planner.view(int_param(req, "state", 0, 1 << 30, 0))); });
    });
    http.Post("/api/update", [this](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] { send_json(res, planner.update(body_json(req))); });
    });
    http.Post("/api/undo", [this](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] {
        send_json(res, planner.undo(int_member(body_json(req), "state", 0, 1 << 30, 0)));
      });
    });
    http.Post("/api/add", [this](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] {
        const json body = body_json(req);
        const int state = int_member(body, "state", 0, 1 << 30, 0);
        const core::JsonNode root(body, "request", "");
        root.only_keys({"model", "state"});
        send_json(res,
                  planner.add_camera(root.has("model") ? root.at("model").string() : "", state));
      });
    });
    http.Post("/api/remove", [this](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] {
        const json body = body_json(req);
        const int state = int_member(body, "state", 0, 1 << 30, 0);
        const core::JsonNode root(body, "request", "");
        root.only_keys({"camera", "state"});
        send_json(res, planner.remove_camera(root.at("camera").integer_in(0, 1 << 30), state));
      });
    });
    http.Post("/api/save", [this](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] {
        const json body = body_json(req);
        const core::JsonNode root(body, "request", "");
        if (!body.is_object()) root.fail("expected a JSON object");
        root.only_keys({"name"});
        send_json(res, planner.save(root.at("name").string()));
      });
    });
    http.Post("/api/optimise", [this](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] { send_json(res, {{"job", jobs.start_optimise(body_json(req))->id()}}); });
    });
    http.Post("/api/check_exact", [this](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] {
        const json body = body_json(req);
        core::JsonNode(body, "request", "").only_keys({});
        send_json(res, {{"job", jobs.start_exact()->id()}});
      });
    });
    http.Post("/api/cancel", [this](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] {
        const int id = int_member(body_json(req), "job", 0, 1 << 30, -1);
        jobs.get(id)->cancel();
        send_json(res, {{"job", id}, {"cancelling", true}});
      });
    });
    // Server-sent events of one job (EventSource): each event as `data: JSON`, from the
    // event `from` on; the stream ends after the job's "done" event.
    http.Get("/api/events", [this](const httplib::Request& req, httplib::Response& res) {
      guarded(res, [&] {
        std::shared_ptr<detail::Job> job = jobs.get(int_param(req, "job", 0, 1 << 30, -1));
        auto next = std::make_shared<std::size_t>(
            static_cast<std::size_t>(int_param(req, "from", 0, 1 << 30, 0)));
        res.set_header("Cache-Control", "no-store");
        res.set_chunked_content_provider(
            "text/event-stream", [this, job, next](std::size_t, httplib::DataSink& sink) {
              bool finished = false;
              const auto events = job->events_from(*next, std::chrono::milliseconds(250), finished);
              std::string text;
              for (const json& e : events) text += "data: " + e.dump() + "\n\n";
              *next += events.size();
              if (text.empty()) text = ": waiting\n\n";  // finds a closed connection
              if (!sink.write(text.data(), text.size())) return false;
              if ((finished && events.empty()) || stopping.load()) sink.done();
              return true;
            });
      });
    });
  }
};

Server::Server(Planner& planner, ServerOptions options)
    : impl_(std::make_unique<Impl>(planner, std::move(options))) {
  Impl& m = *impl_;
  if (m.options.token.empty()) m.options.token = random_token();
  for (const auto& [path, file] : kThreeFiles) {
    const std::string full = m.options.three_dir + "/" + file;
    if (!std::ifstream(full)) {
      throw core::OptionError("three-dir", full +
                                               " cannot be read (install Debian's libjs-three, or "
                                               "pass the directory holding three.min.js)");
    }
  }
  m.routes();
  if (m.options.port == 0) {
    m.port = m.http.bind_to_any_port(m.options.host);
  } else if (m.http.bind_to_port(m.options.host, m.options.port)) {
    m.port = m.options.port;
  } else {
    m.port = -1;
  }
  if (m.port <= 0) {
    throw core::OptionError("port", "cannot listen on " + m.options.host + ":" +
                                        std::to_string(m.options.port) +
                                        " (in use, or not an address of this machine); choose "
                                        "another --port, or 0 for any free one");
  }
}

Server::~Server() {
  impl_->stopping = true;
  impl_->jobs.stop_all();
  impl_->http.stop();
}

int Server::port() const { return impl_->port; }

std::string Server::url() const {
  const std::string& host = impl_->options.host;
  const std::string shown = host.find(':') != std::string::npos ? "[" + host + "]" : host;
  return "http://" + shown + ":" + std::to_string(impl_->port) + "/?token=" + impl_->options.token;
}

void Server::run(const std::atomic<bool>& stop) {
  Impl& m = *impl_;
  std::thread listener([&m] { m.http.listen_after_bind(); });
  while (!stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  m.stopping = true;
  m.jobs.stop_all();
  m.http.stop();
  listener.join();
}

}  // namespace camplace::serve
