//! Integration tests of the file formats, compiled as one binary.

mod gsd;
