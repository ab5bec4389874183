// Before any test: two requests to a throwaway cpp-httplib server whose jobs run on its listening
// thread, joined on the main thread. They initialise httplib's function-local statics on the
// request path before any test server starts: the method set of Server::parse_request_line, and
// the chunked stream's end marker (`static const std::string done_marker`, written when a content
// provider calls DataSink::done(), as /events does when a scene closes or the server stops).
//
// Why (ThreadSanitizer, README "Fuzzing and the thread sanitizer"): a static is initialised once
// under __cxa_guard_acquire/release, which TSan intercepts, but later uses check the guard with a
// plain load inside the uninstrumented libcpp-httplib.so, which TSan cannot see. The first worker
// to parse a request built the set; another worker comparing against it (memcmp, intercepted)
// was reported as racing with that construction; so was one worker's send() of done_marker with
// the worker that constructed it (ServerEvents.TooManyStreamsAre429, in CI). The real order exists (the guard); started from
// a joined thread, every later thread is also ordered after it for TSan. A suppression cannot be
// this narrow: every worker's creation stack passes through libcpp-httplib.so.
#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <functional>
#include <thread>

namespace {

// Runs each connection on the thread that accepted it.
class OnListeningThread : public httplib::TaskQueue {
 public:
  void enqueue(std::function<void()> job) override { job(); }
  void shutdown() override {}
};

class HttplibWarmUp : public ::testing::Environment {
 public:
  void SetUp() override {
    httplib::Server server;
    server.new_task_queue = [] { return new OnListeningThread; };
    server.Get("/", [](const httplib::Request&, httplib::Response& res) {
      res.set_content("ok", "text/plain");
    });
    server.Get("/chunked", [](const httplib::Request&, httplib::Response& res) {
      res.set_chunked_content_provider("text/plain", [](size_t, httplib::DataSink& sink) {
        sink.write("ok", 2);
        sink.done();
        return true;
      });
    });
    const int port = server.bind_to_any_port("127.0.0.1");
    ASSERT_GT(port, 0) << "httplib warm-up: cannot bind";
    std::thread listener([&] { server.listen_after_bind(); });
    while (!server.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    httplib::Client client("127.0.0.1", port);
    const auto res = client.Get("/");
    const auto chunked = client.Get("/chunked");
    server.stop();
    listener.join();
    ASSERT_TRUE(res) << "httplib warm-up: no answer";
    EXPECT_EQ(res->status, 200);
    ASSERT_TRUE(chunked) << "httplib warm-up: no answer to the chunked request";
    EXPECT_EQ(chunked->body, "ok");
  }
};

[[maybe_unused]] ::testing::Environment* const kWarmUp =
    ::testing::AddGlobalTestEnvironment(new HttplibWarmUp);

}  // namespace
