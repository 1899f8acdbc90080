#pragma once
// Every model's control assembler (est/loop/control_assembler.hpp), for the estimators that take any model.
#include "est/loop/controls/bicycle.hpp"
#include "est/loop/controls/diff_drive.hpp"
#include "est/loop/controls/holonomic.hpp"
#include "est/loop/controls/odometry.hpp"
#include "est/loop/controls/omni.hpp"
#include "est/loop/controls/velocity.hpp"
