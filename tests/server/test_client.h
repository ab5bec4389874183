// The server tests' HTTP client: httplib's, with replies that fail the test cleanly when a request
// got none. httplib::Result's `->` on a request that failed (a read timeout, a refused connection)
// reads through a null pointer: undefined behaviour, which UBSan reports as a finding and which
// hides the real failure. A Reply throws instead, naming httplib's error; GoogleTest reports the
// exception as the test's failure.
#pragma once

#include <httplib.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace penumbra::server::test {

class Reply : public httplib::Result {
 public:
  Reply(httplib::Result&& result) : httplib::Result(std::move(result)) {}  // NOLINT: implicit

  const httplib::Response& operator*() const { return checked(); }
  httplib::Response& operator*() { return const_cast<httplib::Response&>(checked()); }
  const httplib::Response* operator->() const { return &checked(); }
  httplib::Response* operator->() { return const_cast<httplib::Response*>(&checked()); }
  const httplib::Response& value() const { return checked(); }

 private:
  const httplib::Response& checked() const {
    if (!*this) throw std::runtime_error("no HTTP answer: " + httplib::to_string(error()));
    return httplib::Result::value();
  }
};

// Every request method answers a Reply; everything else is httplib::Client's.
class TestClient : public httplib::Client {
 public:
  using httplib::Client::Client;

  template <class... Args>
  Reply Get(Args&&... args) { return httplib::Client::Get(std::forward<Args>(args)...); }
  // For headers written in braces, which a forwarded argument cannot take.
  Reply Get(const std::string& path, const httplib::Headers& headers) {
    return httplib::Client::Get(path, headers);
  }
  template <class... Args>
  Reply Head(Args&&... args) { return httplib::Client::Head(std::forward<Args>(args)...); }
  template <class... Args>
  Reply Post(Args&&... args) { return httplib::Client::Post(std::forward<Args>(args)...); }
  template <class... Args>
  Reply Put(Args&&... args) { return httplib::Client::Put(std::forward<Args>(args)...); }
  template <class... Args>
  Reply Patch(Args&&... args) { return httplib::Client::Patch(std::forward<Args>(args)...); }
  template <class... Args>
  Reply Delete(Args&&... args) { return httplib::Client::Delete(std::forward<Args>(args)...); }
  template <class... Args>
  Reply Options(Args&&... args) { return httplib::Client::Options(std::forward<Args>(args)...); }
};

}  // namespace penumbra::server::test
