#version 450 core
// No colour output: a query box only tests depth (colour and depth writes are off).
void main() {}
