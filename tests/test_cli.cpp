// written by the input-validation test helper
