"""PettingZoo and Gymnasium views of the batched runtime."""
