// PLACEHOLDER until the carmen tests land (this session).
#include <catch2/catch.hpp>
