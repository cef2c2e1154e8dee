// Everything of the vwg core in one include.
#pragma once

#include "vwg/actor.hpp"
#include "vwg/alphabet.hpp"
#include "vwg/backend.hpp"
#include "vwg/blob.hpp"
#include "vwg/engine.hpp"
#include "vwg/error.hpp"
#include "vwg/event.hpp"
#include "vwg/generator.hpp"
#include "vwg/hash.hpp"
#include "vwg/random.hpp"
#include "vwg/semantics.hpp"
#include "vwg/text.hpp"
#include "vwg/value.hpp"
#include "vwg/world_string.hpp"
#include "vwg/version.hpp"
