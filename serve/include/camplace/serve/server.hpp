#pragma once
/// The HTTP server of `camplace serve` (docs/serve.md), on cpp-httplib (Debian's
/// libcpp-httplib-dev): the planner page, its three.js files and a JSON API over a Planner,
/// every request checked for the session's token. Long work (optimise, check exactly) runs on
/// worker threads and streams server-sent events.
#include <atomic>
#include <cstddef>
#include <memory>
#include <string>

#include "camplace/serve/planner.hpp"

namespace camplace::serve {

/// Where Debian's libjs-three installs three.js.
inline constexpr const char* kThreeDir = "/usr/share/javascript/three";

struct ServerOptions {
  std::string host = "127.0.0.1";  ///< the address to listen on
  int port = 8765;                 ///< 0 = any free port
  /// Required on every request (query parameter `token` or header X-Camplace-Token); empty =
  /// 32 random hex digits.
  std::string token;
  std::string three_dir = kThreeDir;        ///< libjs-three's directory
  std::size_t max_request_bytes = 1 << 20;  ///< larger request bodies get 413
  int threads = 32;  ///< connections served at once (an event stream holds one)
};

class Server {
 public:
  /// Binds the port (core::OptionError("port", ...) when it cannot) and checks that the
  /// three.js files are readable (core::OptionError("three-dir", ...)).
  Server(Planner& planner, ServerOptions options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  int port() const;
  /// http://HOST:PORT/?token=TOKEN, the page to open.
  std::string url() const;
  /// Serves until `stop` is raised (checked every 50 ms), then cancels the long work, waits for
  /// it and stops listening.
  void run(const std::atomic<bool>& stop);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace camplace::serve
