// PLACEHOLDER until the victoria tests land (this session).
#include <catch2/catch.hpp>
