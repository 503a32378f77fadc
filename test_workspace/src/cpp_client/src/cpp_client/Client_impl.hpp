// Your implementation of the component Client: this file is yours.
// colcon-robmosys created it once and never writes it again; the skeleton
// src-skel/cpp_client/Client_impl.hpp of the generated package shows
// what the model asks for after the model changes.
// Copyright and license: those of the package cpp_client (package.xml).

#pragma once

#include <memory>

#include "cpp_client/Client.hpp"

namespace cpp_client
{

/// The component Client with its user-written functions.
class Client_impl : public Client
{
public:
  using Client::Client;

protected:
  void fAsk() override;
  void fReset() override;

private:
  /// How many times fAsk asked since configure.
  int64_t n_ = 0;
};

}  // namespace cpp_client
